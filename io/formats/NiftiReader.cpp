// NIfTI-1 and NIfTI-2 through nifticlib's nifti2 API, which reads both.

#include "io/formats/NiftiImage.h"
#include "io/formats/Readers.h"
#include "io/formats/SampleFile.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <nifti2_io.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

namespace gvr {

namespace {

/// What nifticlib does not tell: the header's size, and vox_offset as written
/// (nifticlib quietly moves an offset it cannot use to the end of the header).
struct RawHeader {
    int size = 0;       // 348 (NIfTI-1) or 540 (NIfTI-2)
    bool swap = false;  // written in the other byte order
    double voxOffset = 0.0;
    std::int64_t dimensions = 0;         // dim[0], as written
    double pixdim[3] = {1.0, 1.0, 1.0};  // as written: nifticlib turns 0 and NaN into 1
};

/// A header field, @a swap when the file was written in the other byte order.
template <typename T>
T fieldAt(const unsigned char* bytes, std::size_t offset, bool swap) {
    return loadWord<T>(bytes + offset, swap != hostIsBigEndian());
}

/// nifticlib only says "failed" on stderr, so read the header ourselves first to
/// tell a truncated or foreign file from a corrupt header.
RawHeader readRawHeader(const std::string& path) {
    gzFile file = gzopen(path.c_str(), "rb");
    if (!file) throw InputError(path, "cannot open file");
    unsigned char bytes[540] = {};
    const int got = gzread(file, bytes, sizeof bytes);
    gzclose(file);
    if (got < 4) throw InputError(path, "file is too short for a NIfTI header");
    for (bool swap : {false, true}) {
        const std::int32_t size = fieldAt<std::int32_t>(bytes, 0, swap);
        if ((size != 348 && size != 540) || got < size) continue;
        RawHeader header;
        header.size = size;
        header.swap = swap;
        // NIfTI-1 writes vox_offset as a float, NIfTI-2 as an int64.
        header.voxOffset =
            size == 348 ? double(fieldAt<float>(bytes, 108, swap)) : double(fieldAt<std::int64_t>(bytes, 168, swap));
        header.dimensions =
            size == 348 ? fieldAt<std::int16_t>(bytes, 40, swap) : fieldAt<std::int64_t>(bytes, 16, swap);
        for (int axis = 0; axis < 3; ++axis) {
            header.pixdim[axis] = size == 348 ? double(fieldAt<float>(bytes, 80 + 4 * axis, swap))
                                              : fieldAt<double>(bytes, 112 + 8 * axis, swap);
        }
        return header;
    }
    const std::int32_t size = fieldAt<std::int32_t>(bytes, 0, false);
    if (size == 348 || size == 540) throw InputError(path, "file is too short for its NIfTI header");
    throw InputError(path, "corrupt NIfTI header: sizeof_hdr is " + std::to_string(size) +
                               " (expected 348 for NIfTI-1 or 540 for NIfTI-2)");
}

/// nifticlib adds each header extension to its list by copying the whole list, so
/// a header with very many of them took long to read: one with more than this many
/// is refused first.
constexpr int kMaxExtensions = 1000;

void checkExtensionCount(const std::string& path, const RawHeader& header) {
    gzFile file = gzopen(path.c_str(), "rb");
    if (!file) return;
    std::unique_ptr<gzFile_s, int (*)(gzFile)> closer(file, gzclose);
    unsigned char extender[4] = {};
    if (gzseek(file, header.size, SEEK_SET) < 0 || gzread(file, extender, 4) != 4 || extender[0] == 0) return;
    z_off_t position = header.size + 4;
    for (int count = 0;; ++count) {
        if (header.voxOffset > 0.0 && double(position) + 8.0 > header.voxOffset) return;
        unsigned char bytes[8];
        if (gzread(file, bytes, 8) != 8) return;  // what is left is nifticlib's to judge
        const std::int32_t esize = fieldAt<std::int32_t>(bytes, 0, header.swap);
        if (esize < 16 || esize % 16 != 0) return;  // no extension nifticlib would read
        if (count == kMaxExtensions) {
            throw InputError(
                path, "corrupt NIfTI header: more than " + std::to_string(kMaxExtensions) + " header extensions");
        }
        position += esize;
        if (gzseek(file, position, SEEK_SET) < 0) return;
    }
}

/// The samples must start where the header says, after the header in a one-file
/// NIfTI (anywhere in a .hdr/.img pair's .img), at a whole byte.
void checkVoxOffset(const std::string& path, const RawHeader& header, const nifti_image& image) {
    const bool oneFile = std::string(image.iname) == std::string(image.fname);
    const double lowest = oneFile ? double(header.size + 4) : 0.0;
    const double offset = header.voxOffset;
    if (!(offset >= lowest) || offset != std::floor(offset) || double(image.iname_offset) != offset) {
        std::ostringstream text;
        text << "corrupt NIfTI header: vox_offset " << offset
             << " is not a usable data offset (a whole number of bytes, at least " << lowest << ")";
        throw InputError(path, text.str());
    }
}

struct Layout {
    SampleType type;
    int channels;
};

Layout layoutOf(const nifti_image& image, const std::string& path) {
    switch (image.datatype) {
        case NIFTI_TYPE_UINT8:
            return {SampleType::UInt8, 1};
        case NIFTI_TYPE_INT8:
            return {SampleType::Int8, 1};
        case NIFTI_TYPE_UINT16:
            return {SampleType::UInt16, 1};
        case NIFTI_TYPE_INT16:
            return {SampleType::Int16, 1};
        case NIFTI_TYPE_UINT32:
            return {SampleType::UInt32, 1};
        case NIFTI_TYPE_INT32:
            return {SampleType::Int32, 1};
        case NIFTI_TYPE_FLOAT32:
            return {SampleType::Float32, 1};
        case NIFTI_TYPE_FLOAT64:
            return {SampleType::Float64, 1};
        case NIFTI_TYPE_RGB24:
            return {SampleType::UInt8, 3};
        default:
            break;
    }
    const char* name = nifti_datatype_to_string(image.datatype);
    throw InputError(path, std::string("unsupported NIfTI datatype ") + name + " (" + std::to_string(image.datatype) +
                               "); gvr reads uint8, int8, uint16, int16, uint32, int32, "
                               "float32, float64 and RGB24");
}

/// Without an sform the voxel sizes come from pixdim, where nifticlib silently
/// replaces a 0 or a NaN with 1 mm: say so, since every distance then is a guess.
void warnAboutMissingVoxelSizes(const RawHeader& header, DenseVolume& volume) {
    for (int axis = 0; axis < 3; ++axis) {
        const double size = header.pixdim[axis];
        if (size != 0.0 && std::isfinite(size)) continue;
        std::ostringstream text;
        text << "pixdim[" << axis + 1 << "] is " << size << ", not a voxel size: using 1 mm along axis "
             << "xyz"[axis];
        volume.warnings.push_back(text.str());
    }
}

/// sform if set, else qform, else the voxel sizes alone (NIfTI's "method 1").
openvdb::math::Mat4d worldFromIndexOf(const std::string& path, const nifti_image& image, const RawHeader& header,
                                      DenseVolume& volume) {
    const nifti_dmat44* matrix = nullptr;
    if (image.sform_code > 0)
        matrix = &image.sto_xyz;
    else if (image.qform_code > 0)
        matrix = &image.qto_xyz;
    double rows[3][4] = {{std::abs(image.dx), 0, 0, 0}, {0, std::abs(image.dy), 0, 0}, {0, 0, std::abs(image.dz), 0}};
    if (matrix != &image.sto_xyz) warnAboutMissingVoxelSizes(header, volume);
    if (matrix) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) {
                rows[r][c] = matrix->m[r][c];
                if (!std::isfinite(rows[r][c])) {
                    throw InputError(path, std::string("corrupt NIfTI header: the ") +
                                               (matrix == &image.sto_xyz ? "sform" : "qform") +
                                               " holds a value that is not finite");
                }
            }
        }
    } else {
        volume.warnings.push_back("no sform or qform: orientation unknown, using voxel sizes only");
    }
    return worldFromIndexRows(rows);
}

}  // namespace

DenseVolume readNifti(const std::string& path, const ReadOptions& options) {
    const RawHeader header = readRawHeader(path);
    // nifticlib reads a dim[0] of 0 as a volume all the same, of sizes no header gave
    // (one above 7 it refuses itself).
    if (header.dimensions < 1) {
        throw InputError(path, "corrupt NIfTI header: dim[0] is " + std::to_string(header.dimensions) +
                                   "; it counts the dimensions, 1 to 7");
    }
    checkExtensionCount(path, header);
    nifti_set_debug_level(0);
    NiftiImagePtr image(nifti_image_read(path.c_str(), /*read_data=*/0));
    if (!image) throw InputError(path, "corrupt NIfTI header (nifticlib could not parse it)");
    checkVoxOffset(path, header, *image);

    DenseVolume volume;
    const Layout layout = layoutOf(*image, path);
    volume.type = layout.type;
    volume.channels = layout.channels;
    volume.dims = {image->nx, image->ny, image->nz};
    for (int d = 5; d <= 7; ++d) {
        if (image->dim[0] >= d && image->dim[d] > 1) {
            throw InputError(
                path, "has " + std::to_string(image->dim[0]) + " dimensions; gvr reads 3D volumes and 4D series");
        }
    }
    const std::int64_t volumeCount = image->dim[0] >= 4 ? std::max<std::int64_t>(image->nt, 1) : 1;
    if (options.volumeIndex < 0 || options.volumeIndex >= volumeCount) {
        throw InputError(path, "`volume=" + std::to_string(options.volumeIndex) + "`" +
                                   " is out of range: the file holds " + std::to_string(volumeCount) +
                                   " volume(s), 0.." + std::to_string(volumeCount - 1));
    }
    if (volumeCount > 1) {
        volume.warnings.push_back("4D series of " + std::to_string(volumeCount) + " volumes: reading volume " +
                                  std::to_string(options.volumeIndex) + " (choose with `volume`)");
    }
    volume.worldFromIndex = worldFromIndexOf(path, *image, header, volume);
    if (image->scl_slope != 0.0 && std::isfinite(image->scl_slope) && std::isfinite(image->scl_inter)) {
        volume.slope = image->scl_slope;
        volume.intercept = image->scl_inter;
    }
    volume.niftiCodes =
        NiftiCodes{image->sform_code, image->qform_code, SPACE_TIME_TO_XYZT(image->xyz_units, image->time_units)};

    reserveSamples(volume, path);  // the sample reader allocates as data arrives
    // The samples are read with zlib rather than nifticlib, which prints to stderr
    // on a short read and frees the caller's buffer.
    const std::uint64_t offset =
        std::uint64_t(image->iname_offset) + volume.sampleBytes() * std::uint64_t(options.volumeIndex);
    readGzipSamples(image->iname, offset, image->byteorder == 2 /* MSB first */, volume);
    if (options.progress) options.progress(1.0);
    return volume;
}

}  // namespace gvr
