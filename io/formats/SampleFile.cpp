#include "io/formats/SampleFile.h"

#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

namespace gvr {

namespace {

/// Buffers grow by this much as decompressed bytes arrive.
constexpr std::uint64_t kGrowBytes = 64u << 20;

void toHostOrder(DenseVolume& volume, bool bigEndian) {
    const std::size_t width = bytesPerSample(volume.type);
    gvr::toHostOrder(volume.samples.data(), volume.samples.size() / width, width, bigEndian);
}

}  // namespace

void readPlainSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume) {
    const std::uint64_t size = std::filesystem::file_size(file);
    const std::uint64_t needed = offset + volume.sampleBytes();
    if (size < needed) {
        throw InputError(file, "truncated: voxel data needs " + std::to_string(needed) + " bytes, the file has " +
                                   std::to_string(size));
    }
    if (size > needed) {
        volume.warnings.push_back(file + ": " + std::to_string(size - needed) +
                                  " bytes after the voxel data are ignored");
    }
    volume.samples.assign(volume.sampleBytes(), 0);
    std::ifstream in(file, std::ios::binary);
    in.seekg(std::streamoff(offset));
    in.read(reinterpret_cast<char*>(volume.samples.data()), std::streamsize(volume.samples.size()));
    if (!in) throw InputError(file, "read error");
    toHostOrder(volume, bigEndian);
}

void readGzipSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume) {
    gzFile stream = gzopen(file.c_str(), "rb");
    if (!stream) throw InputError(file, "cannot open file");
    volume.samples.clear();
    volume.samples.reserve(volume.sampleBytes());
    const std::uint64_t expected = volume.sampleBytes();
    std::uint64_t filled = 0;
    if (gzseek(stream, z_off_t(offset), SEEK_SET) == z_off_t(offset)) {
        while (filled < expected) {
            const std::uint64_t chunk = std::min<std::uint64_t>(expected - filled, kGrowBytes);
            volume.samples.resize(filled + chunk);  // within the reserve: no copy
            const int got = gzread(stream, volume.samples.data() + filled, unsigned(chunk));
            if (got <= 0) break;
            filled += std::uint64_t(got);
        }
        // Read on to the end, so that zlib checks the gzip CRC of what was read.
        std::vector<unsigned char> rest(1 << 16);
        while (filled == expected && gzread(stream, rest.data(), unsigned(rest.size())) > 0) {
        }
    }
    int code = Z_OK;
    const std::string zlibMessage = gzerror(stream, &code);
    gzclose(stream);
    volume.samples.resize(filled);
    if (code == Z_DATA_ERROR || code == Z_STREAM_ERROR || code == Z_MEM_ERROR) {
        throw InputError(file, "corrupt compressed data (zlib: " + zlibMessage + ")");
    }
    // zlib's word for a file that ends early; with every sample read, what is missing
    // is the trailer whose CRC would vouch for them.
    if (code == Z_BUF_ERROR && filled == expected) {
        throw InputError(file, "truncated: the compressed stream ends before its checksum");
    }
    if (filled != expected) {
        throw InputError(file, "truncated: voxel data holds " + std::to_string(filled) + " bytes, expected " +
                                   std::to_string(expected));
    }
    toHostOrder(volume, bigEndian);
}

void readDeflatedSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume) {
    std::ifstream in(file, std::ios::binary);
    in.seekg(std::streamoff(offset));
    z_stream stream{};
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw InputError(file, "zlib initialisation failed");
    volume.samples.clear();
    volume.samples.reserve(volume.sampleBytes());
    const std::uint64_t expected = volume.sampleBytes();
    std::vector<unsigned char> chunk(1 << 20), beyond(1 << 16);
    int status = Z_OK;
    // Inflate to the stream's end even after the last sample, so that zlib checks
    // the stream's Adler-32 or CRC; output past the samples goes to scratch.
    while (status == Z_OK) {
        if (stream.avail_out == 0) {  // grown in steps, within the reserve
            const std::uint64_t produced = stream.total_out;
            if (produced < expected) {
                volume.samples.resize(std::min<std::uint64_t>(expected, produced + kGrowBytes));
                stream.next_out = volume.samples.data() + produced;
                stream.avail_out = uInt(volume.samples.size() - produced);
            } else {
                stream.next_out = beyond.data();
                stream.avail_out = uInt(beyond.size());
            }
        }
        if (stream.avail_in == 0) {
            in.read(reinterpret_cast<char*>(chunk.data()), std::streamsize(chunk.size()));
            stream.next_in = chunk.data();
            stream.avail_in = uInt(in.gcount());
            if (stream.avail_in == 0) break;
        }
        status = inflate(&stream, Z_NO_FLUSH);
    }
    const std::uint64_t produced = stream.total_out;
    inflateEnd(&stream);
    volume.samples.resize(std::min(produced, expected));
    if (status != Z_OK && status != Z_STREAM_END) {
        throw InputError(file, "corrupt compressed voxel data (zlib error " + std::to_string(status) + ")");
    }
    if (produced < expected) {
        throw InputError(file, "truncated: compressed voxel data inflates to " + std::to_string(produced) +
                                   " bytes, expected " + std::to_string(expected));
    }
    if (status != Z_STREAM_END) throw InputError(file, "truncated: the compressed stream ends before its checksum");
    toHostOrder(volume, bigEndian);
}

}  // namespace gvr
