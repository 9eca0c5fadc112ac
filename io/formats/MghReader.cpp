// FreeSurfer MGH, and MGZ (the same, gzip'd). A 284-byte big-endian header, then
// the frames one after the other. Layout from FreeSurfer's mghformat documentation.

#include "io/formats/Readers.h"
#include "io/formats/SampleFile.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <zlib.h>

#include <cstring>

namespace gvr {

namespace {

constexpr std::size_t kHeaderBytes = 284;

/// Reads big-endian fields from the header in order.
class BigEndianCursor {
public:
    explicit BigEndianCursor(const unsigned char* bytes) : mBytes(bytes) {}

    std::int32_t int32() { return read<std::int32_t>(); }
    std::int16_t int16() { return read<std::int16_t>(); }
    float float32() { return read<float>(); }

private:
    template <typename T>
    T read() {
        const T value = loadWord<T>(mBytes + mOffset, /*storedBigEndian=*/true);
        mOffset += sizeof(T);
        return value;
    }
    const unsigned char* mBytes;
    std::size_t mOffset = 0;
};

struct GzipFile {  // closes on every path out
    explicit GzipFile(const std::string& path) : handle(gzopen(path.c_str(), "rb")) {
        if (!handle) throw InputError(path, "cannot open file");
    }
    ~GzipFile() { gzclose(handle); }
    GzipFile(const GzipFile&) = delete;
    GzipFile& operator=(const GzipFile&) = delete;
    gzFile handle;
};

SampleType sampleTypeOf(std::int32_t code, const std::string& path) {
    switch (code) {
        case 0:
            return SampleType::UInt8;
        case 1:
            return SampleType::Int32;
        case 3:
            return SampleType::Float32;
        case 4:
            return SampleType::Int16;
        default:
            break;
    }
    throw InputError(
        path, "unsupported MGH data type " + std::to_string(code) + " (gvr reads 0 uchar, 1 int, 3 float, 4 short)");
}

/// FreeSurfer's vox2ras: direction cosines times voxel size, centred on c_ras.
openvdb::math::Mat4d worldFromIndexOf(BigEndianCursor& cursor, const DenseVolume& volume, bool goodRas) {
    double spacing[3], cosines[3][3], centre[3];
    for (double& s : spacing) s = cursor.float32();
    for (auto& axis : cosines) {
        for (double& c : axis) c = cursor.float32();
    }
    for (double& c : centre) c = cursor.float32();
    if (!goodRas) {  // FreeSurfer's default: coronal slices, LIA
        const double lia[3][3] = {{-1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
        std::memcpy(cosines, lia, sizeof cosines);
    }
    double rows[3][4];
    for (int r = 0; r < 3; ++r) {
        double offset = centre[r];
        for (int axis = 0; axis < 3; ++axis) {
            rows[r][axis] = cosines[axis][r] * spacing[axis];
            offset -= rows[r][axis] * (volume.dims[axis] / 2.0);
        }
        rows[r][3] = offset;
    }
    return worldFromIndexRows(rows);
}

}  // namespace

DenseVolume readMgh(const std::string& path, const ReadOptions& options) {
    GzipFile file(path);
    unsigned char header[kHeaderBytes];
    if (gzread(file.handle, header, kHeaderBytes) != int(kHeaderBytes)) {
        throw InputError(path, "file is too short for an MGH header");
    }
    BigEndianCursor cursor(header);
    const std::int32_t version = cursor.int32();
    if (version != 1) {
        throw InputError(path, "corrupt MGH header: version is " + std::to_string(version) + " (expected 1)");
    }
    DenseVolume volume;
    for (auto& d : volume.dims) d = cursor.int32();
    const std::int32_t frames = cursor.int32();
    if (frames < 1) {
        throw InputError(path,
                         "corrupt MGH header: nframes is " + std::to_string(frames) + "; a volume has at least one");
    }
    volume.type = sampleTypeOf(cursor.int32(), path);
    cursor.int32();  // degrees of freedom: unused
    const bool goodRas = cursor.int16() > 0;
    volume.worldFromIndex = worldFromIndexOf(cursor, volume, goodRas);
    volume.modality = "MR";
    if (options.volumeIndex < 0 || options.volumeIndex >= frames) {
        throw InputError(path, "`volume=" + std::to_string(options.volumeIndex) + "`" +
                                   " is out of range: the file holds " + std::to_string(frames) + " frame(s)");
    }
    reserveSamples(volume, path);  // the sample reader allocates as data arrives

    readGzipSamples(path, kHeaderBytes + volume.sampleBytes() * std::uint64_t(options.volumeIndex),
                    /*bigEndian=*/true, volume);
    if (options.progress) options.progress(1.0);
    return volume;
}

}  // namespace gvr
