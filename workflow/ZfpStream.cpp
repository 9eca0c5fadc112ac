#include "workflow/ZfpStream.h"

#include "io/guard/AtomicFile.h"
#include "io/guard/ByteOrder.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"

#include <zfp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

namespace gvr {

namespace {

constexpr char kMagic[8] = {'G', 'V', 'R', 'Z', 'F', 'P', '\0', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kFixedHeaderBytes = 40;
constexpr std::size_t kCountsOffset = kFixedHeaderBytes;

std::size_t headerBytes(int channels) { return kFixedHeaderBytes + sizeof(std::uint64_t) * std::size_t(channels); }

struct ZfpDeleter {
    void operator()(zfp_stream* stream) const { zfp_stream_close(stream); }
    void operator()(zfp_field* field) const { zfp_field_free(field); }
    void operator()(bitstream* bits) const { stream_close(bits); }
};
template <typename T>
using ZfpPtr = std::unique_ptr<T, ZfpDeleter>;

/// zfp's accuracy mode cuts at the power of two at or below the tolerance t.
double accuracyCut(double tolerance) {
    int exponent = 0;
    std::frexp(tolerance, &exponent);  // t = m 2^exponent, m in [0.5, 1)
    return std::ldexp(1.0, exponent - 1);
}

/// Coding the samples times s = accuracyCut(t) / t, in (0.5, 1], and dividing by s
/// after decoding moves zfp's cut to exactly t: any tolerance can be asked for, and
/// stream sizes vary smoothly with it. Fixed rate needs no scale (1).
double sampleScale(const ZfpSettings& settings) {
    return settings.mode == ZfpMode::FixedRate ? 1.0 : accuracyCut(settings.parameter) / settings.parameter;
}

/// A zfp stream set to @a settings; @a effective receives the parameter as zfp applies it.
ZfpPtr<zfp_stream> openStream(const ZfpSettings& settings, double& effective) {
    ZfpPtr<zfp_stream> zfp(zfp_stream_open(nullptr));
    if (settings.mode == ZfpMode::FixedRate) {
        effective = zfp_stream_set_rate(zfp.get(), settings.parameter, zfp_type_float, 3, zfp_false);
    } else {
        zfp_stream_set_accuracy(zfp.get(), accuracyCut(settings.parameter));  // exact: a power of two
        effective = settings.parameter;
    }
    return zfp;
}

/// The samples as zfp codes them (see sampleScale).
std::vector<float> scaledSamples(const FloatVolume& volume, double scale) {
    std::vector<float> scaled(volume.values);
    if (scale != 1.0) {
        for (float& v : scaled) v = float(v * scale);
    }
    return scaled;
}

/// One channel of interleaved samples as a strided 3D field, so no channel is copied out.
ZfpPtr<zfp_field> channelField(float* values, const openvdb::Coord& dims, int channels, int channel) {
    ZfpPtr<zfp_field> field(zfp_field_3d(values + channel, zfp_type_float, std::size_t(dims.x()), std::size_t(dims.y()),
                                         std::size_t(dims.z())));
    const std::ptrdiff_t sx = channels, sy = sx * dims.x(), sz = sy * dims.y();
    zfp_field_set_stride_3d(field.get(), sx, sy, sz);
    return field;
}

/// Compresses @a field onto the end of @a bytes. @return the compressed byte count.
std::uint64_t compressOnto(std::string& bytes, zfp_stream* zfp, zfp_field* field) {
    const std::size_t start = bytes.size();
    bytes.resize(start + zfp_stream_maximum_size(zfp, field));
    const ZfpPtr<bitstream> bits(stream_open(bytes.data() + start, bytes.size() - start));
    zfp_stream_set_bit_stream(zfp, bits.get());
    zfp_stream_rewind(zfp);
    const std::size_t size = zfp_compress(zfp, field);
    if (size == 0) throw std::runtime_error("zfp could not compress the volume");
    bytes.resize(start + size);
    return size;
}

struct Header {
    int channels = 1;
    openvdb::Coord dims;
    ZfpSettings settings;
    std::vector<std::uint64_t> channelBytes;
};

/// 4^3 blocks of a field; long double because corrupt dimensions overflow 64 bits.
long double blockCount(const std::array<std::int64_t, 3>& dims) {
    long double blocks = 1;
    for (std::int64_t d : dims) blocks *= (d + 3) / 4;
    return blocks;
}

/// Reads the header of @a bytes and checks it against the file's size, so that
/// nothing is allocated from a number the file does not back.
Header parseHeader(const std::string& bytes, const std::string& path) {
    if (bytes.size() < sizeof kMagic || !std::equal(kMagic, kMagic + sizeof kMagic, bytes.data())) {
        throw InputError(path, "not a gvr zfp stream (no GVRZFP magic)");
    }
    if (bytes.size() < kFixedHeaderBytes) throw InputError(path, "truncated zfp stream header");
    const auto version = loadLittleEndian<std::uint32_t>(bytes.data() + 8);
    if (version != kVersion) {
        throw InputError(path, "unsupported zfp stream version " + std::to_string(version) +
                                   " (this gvr reads version " + std::to_string(kVersion) + ")");
    }
    Header header;
    const auto channels = loadLittleEndian<std::uint32_t>(bytes.data() + 12);
    if (channels != 1 && channels != 3) {
        throw InputError(path, "corrupt zfp stream: " + std::to_string(channels) + " channels (expected 1 or 3)");
    }
    header.channels = int(channels);
    std::array<std::int64_t, 3> dims{};
    for (int a = 0; a < 3; ++a) dims[a] = loadLittleEndian<std::uint32_t>(bytes.data() + 16 + 4 * a);
    const auto mode = loadLittleEndian<std::uint32_t>(bytes.data() + 28);
    if (mode != zfp_mode_fixed_rate && mode != zfp_mode_fixed_accuracy) {
        throw InputError(path, "corrupt zfp stream: unknown mode " + std::to_string(mode));
    }
    header.settings.mode = mode == zfp_mode_fixed_rate ? ZfpMode::FixedRate : ZfpMode::FixedAccuracy;
    header.settings.parameter = loadLittleEndian<double>(bytes.data() + 32);
    if (!(header.settings.parameter > 0.0) || !std::isfinite(header.settings.parameter)) {
        throw InputError(path, "corrupt zfp stream: mode parameter " + std::to_string(header.settings.parameter));
    }
    if (bytes.size() < headerBytes(header.channels)) throw InputError(path, "truncated zfp stream header");
    std::uint64_t payload = 0;
    for (int c = 0; c < header.channels; ++c) {
        const auto count = loadLittleEndian<std::uint64_t>(bytes.data() + kCountsOffset + 8 * c);
        // zfp spends at least one bit on every 4^3 block.
        if (count > bytes.size() || blockCount(dims) > 8.0L * count) {
            throw InputError(path, "corrupt zfp stream: channel " + std::to_string(c) + " claims " +
                                       std::to_string(count) + " bytes for a field of " + std::to_string(dims[0]) +
                                       "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                                       " in a file of " + std::to_string(bytes.size()) + " bytes");
        }
        header.channelBytes.push_back(count);
        payload += count;
    }
    const std::uint64_t expected = headerBytes(header.channels) + payload;
    if (bytes.size() != expected) {
        throw InputError(path,
                         (bytes.size() < expected ? "truncated zfp stream: " : "zfp stream has trailing bytes: ") +
                             std::to_string(bytes.size()) + " bytes, the header implies " + std::to_string(expected));
    }
    checkVolumeFitsInMemory(path, dims, header.channels, sizeof(float));
    header.dims = openvdb::Coord(int(dims[0]), int(dims[1]), int(dims[2]));
    return header;
}

/// Decodes @a count bytes of one channel into @a field.
void decompressChannel(zfp_stream* zfp, zfp_field* field, const char* payload, std::uint64_t count,
                       const std::string& path, int channel) {
    // zfp does not bound its reads, so a corrupt payload is read from a copy padded
    // to the most that any stream of this field can take.
    std::string padded(std::max<std::size_t>(count, zfp_stream_maximum_size(zfp, field)), '\0');
    std::memcpy(padded.data(), payload, count);
    const ZfpPtr<bitstream> bits(stream_open(padded.data(), padded.size()));
    zfp_stream_set_bit_stream(zfp, bits.get());
    zfp_stream_rewind(zfp);
    const std::size_t used = zfp_decompress(zfp, field);
    if (used != count) {
        throw InputError(path, "corrupt zfp stream: channel " + std::to_string(channel) + " decoded from " +
                                   std::to_string(used) + " bytes, the header says " + std::to_string(count));
    }
}

std::string readWholeFile(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) throw InputError(path, "no such file");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    std::string bytes(std::size_t(in.tellg()), '\0');
    in.seekg(0);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    if (!in) throw InputError(path, "cannot read the file");
    return bytes;
}

}  // namespace

std::string encodeZfp(const FloatVolume& volume, const ZfpSettings& settings, double* effectiveParameter) {
    double effective = 0.0;
    const ZfpPtr<zfp_stream> zfp = openStream(settings, effective);
    std::string bytes(kMagic, sizeof kMagic);
    appendLittleEndian(bytes, kVersion);
    appendLittleEndian(bytes, std::uint32_t(volume.channels));
    for (int a = 0; a < 3; ++a) appendLittleEndian(bytes, std::uint32_t(volume.dims[a]));
    appendLittleEndian(
        bytes, std::uint32_t(settings.mode == ZfpMode::FixedRate ? zfp_mode_fixed_rate : zfp_mode_fixed_accuracy));
    appendLittleEndian(bytes, effective);                         // decoding with it sets zfp up exactly as here
    bytes.append(sizeof(std::uint64_t) * volume.channels, '\0');  // the counts, filled in below
    std::vector<float> samples = scaledSamples(volume, sampleScale(settings));
    for (int c = 0; c < volume.channels; ++c) {
        const ZfpPtr<zfp_field> field = channelField(samples.data(), volume.dims, volume.channels, c);
        const std::uint64_t count = compressOnto(bytes, zfp.get(), field.get());
        std::memcpy(bytes.data() + kCountsOffset + 8 * c, &count, sizeof count);
    }
    if (effectiveParameter) *effectiveParameter = effective;
    return bytes;
}

void writeZfpFile(const std::string& path, const std::string& stream) {
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        out.write(stream.data(), std::streamsize(stream.size()));
        out.close();
        if (!out) throw InputError(path, "cannot write the zfp stream");
    });
}

FloatVolume readZfpFile(const std::string& path) {
    const std::string bytes = readWholeFile(path);
    const Header header = parseHeader(bytes, path);
    FloatVolume volume(header.dims, header.channels);
    double ignored = 0.0;
    const ZfpPtr<zfp_stream> zfp = openStream(header.settings, ignored);
    std::size_t offset = headerBytes(header.channels);
    for (int c = 0; c < header.channels; ++c) {
        const ZfpPtr<zfp_field> field = channelField(volume.values.data(), volume.dims, volume.channels, c);
        decompressChannel(zfp.get(), field.get(), bytes.data() + offset, header.channelBytes[c], path, c);
        offset += header.channelBytes[c];
    }
    const double scale = sampleScale(header.settings);
    if (scale != 1.0) {
        for (float& v : volume.values) v = float(v / scale);
    }
    if (!std::all_of(volume.values.begin(), volume.values.end(), [](float v) { return std::isfinite(v); })) {
        throw InputError(path, "corrupt zfp stream: it decodes to NaN or Inf");
    }
    return volume;
}

}  // namespace gvr
