#include "SampleFile.h"

#include "ByteOrder.h"
#include "Error.h"

#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <vector>

namespace gvr {

namespace {

void toHostOrder(DenseVolume& volume, bool bigEndian) {
    const std::size_t width = bytesPerSample(volume.type);
    gvr::toHostOrder(volume.samples.data(), volume.samples.size() / width, width, bigEndian);
}

}  // namespace

void readPlainSamples(const std::string& file, std::uint64_t offset, bool bigEndian,
                      DenseVolume& volume) {
    const std::uint64_t size = std::filesystem::file_size(file);
    const std::uint64_t needed = offset + volume.samples.size();
    if (size < needed) {
        throw InputError(file, "truncated: voxel data needs " + std::to_string(needed) +
                                   " bytes, the file has " + std::to_string(size));
    }
    if (size > needed) {
        volume.warnings.push_back(file + ": " + std::to_string(size - needed) +
                                  " bytes after the voxel data are ignored");
    }
    std::ifstream in(file, std::ios::binary);
    in.seekg(std::streamoff(offset));
    in.read(reinterpret_cast<char*>(volume.samples.data()), std::streamsize(volume.samples.size()));
    if (!in) throw InputError(file, "read error");
    toHostOrder(volume, bigEndian);
}

void readGzipSamples(const std::string& file, std::uint64_t offset, bool bigEndian,
                     DenseVolume& volume) {
    gzFile stream = gzopen(file.c_str(), "rb");
    if (!stream) throw InputError(file, "cannot open file");
    std::uint64_t filled = 0;
    if (gzseek(stream, z_off_t(offset), SEEK_SET) == z_off_t(offset)) {
        while (filled < volume.samples.size()) {
            const unsigned chunk =
                unsigned(std::min<std::uint64_t>(volume.samples.size() - filled, 1u << 30));
            const int got = gzread(stream, volume.samples.data() + filled, chunk);
            if (got <= 0) break;
            filled += std::uint64_t(got);
        }
    }
    gzclose(stream);
    if (filled != volume.samples.size()) {
        throw InputError(file, "truncated: voxel data holds " + std::to_string(filled) +
                                   " bytes, expected " + std::to_string(volume.samples.size()));
    }
    toHostOrder(volume, bigEndian);
}

void readDeflatedSamples(const std::string& file, std::uint64_t offset, bool bigEndian,
                         DenseVolume& volume) {
    std::ifstream in(file, std::ios::binary);
    in.seekg(std::streamoff(offset));
    z_stream stream{};
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw InputError(file, "zlib initialisation failed");
    const std::uint64_t expected = volume.samples.size();
    stream.next_out = volume.samples.data();
    std::vector<unsigned char> chunk(1 << 20);
    int status = Z_OK;
    while (status == Z_OK && stream.total_out < expected) {
        if (stream.avail_out == 0) {  // avail_out is 32-bit: feed large volumes in parts
            stream.avail_out = uInt(std::min<std::uint64_t>(expected - stream.total_out, 1u << 30));
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
    if (status != Z_OK && status != Z_STREAM_END) {
        throw InputError(file, "corrupt compressed voxel data (zlib error " +
                                   std::to_string(status) + ")");
    }
    if (produced < expected) {
        throw InputError(file, "truncated: compressed voxel data inflates to " +
                                   std::to_string(produced) + " bytes, expected " +
                                   std::to_string(expected));
    }
    toHostOrder(volume, bigEndian);
}

}  // namespace gvr
