// Headerless raw samples, laid out as the user says (--raw-dims, --raw-type, ...).

#include "io/formats/Readers.h"
#include "io/formats/SliceSource.h"
#include "io/guard/ByteOrder.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"

#include <filesystem>
#include <fstream>

namespace gvr {

namespace {

class RawSource : public SliceSource {
public:
    RawSource(DenseVolume layout, const std::string& path, const RawLayout& raw)
        : SliceSource(std::move(layout), path), mOffset(raw.headerBytes), mBigEndian(raw.bigEndian) {}

private:
    void readSlices(std::int64_t first, std::int64_t count, unsigned char* destination,
                    const ProgressFn& progress) const override {
        const std::uint64_t bytes = std::uint64_t(count) * sliceBytes();
        std::ifstream in(culprit(), std::ios::binary);
        in.seekg(std::streamoff(mOffset + std::uint64_t(first) * sliceBytes()));
        in.read(reinterpret_cast<char*>(destination), std::streamsize(bytes));
        if (!in) throw InputError(culprit(), "read error at slice " + std::to_string(first));
        const std::size_t width = bytesPerSample(layout().type);
        toHostOrder(destination, bytes / width, width, mBigEndian);
        if (progress) progress(1.0);
    }

    std::uint64_t mOffset;
    bool mBigEndian;
};

/// The file must hold every sample the layout asks for; bytes beyond are reported.
void checkFileSize(const std::string& path, const RawLayout& raw, DenseVolume& layout) {
    const std::uint64_t size = std::filesystem::file_size(path);
    // long double: with dimensions up to 2^30 the product overflows 64 bits.
    const long double needed = (long double)raw.headerBytes + (long double)raw.dims[0] * raw.dims[1] * raw.dims[2] *
                                                                  raw.channels * bytesPerSample(raw.type);
    if ((long double)size < needed) {
        throw InputError(path, "truncated: voxel data needs " + std::to_string(std::uint64_t(needed)) +
                                   " bytes, the file has " + std::to_string(size));
    }
    if ((long double)size > needed) {
        layout.warnings.push_back(path + ": " + std::to_string(size - std::uint64_t(needed)) +
                                  " bytes after the voxel data are ignored");
    }
}

}  // namespace

std::unique_ptr<SliceSource> openRawSource(const std::string& path, const ReadOptions& options) {
    const RawLayout& raw = *options.raw;
    checkDimensions(path, raw.dims);
    DenseVolume layout;
    layout.dims = raw.dims;
    layout.type = raw.type;
    layout.channels = raw.channels;
    setGivenSpacing(options, layout);
    checkFileSize(path, raw, layout);
    return std::make_unique<RawSource>(std::move(layout), path, raw);
}

}  // namespace gvr
