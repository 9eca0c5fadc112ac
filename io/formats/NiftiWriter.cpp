#include "io/formats/NiftiWriter.h"

#include "io/formats/NiftiImage.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"

#include <nifti2_io.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>

namespace gvr {

namespace {

int niftiDatatype(SampleType type) {
    switch (type) {
        case SampleType::UInt8:
            return NIFTI_TYPE_UINT8;
        case SampleType::Int8:
            return NIFTI_TYPE_INT8;
        case SampleType::UInt16:
            return NIFTI_TYPE_UINT16;
        case SampleType::Int16:
            return NIFTI_TYPE_INT16;
        case SampleType::UInt32:
            return NIFTI_TYPE_UINT32;
        case SampleType::Int32:
            return NIFTI_TYPE_INT32;
        case SampleType::Float32:
            return NIFTI_TYPE_FLOAT32;
        case SampleType::Float64:
            break;
    }
    return NIFTI_TYPE_FLOAT64;
}

/// Rounds @a value into T's range; @a clamped counts the values that were
/// outside it by more than rounding (a non-finite value counts and becomes 0).
template <typename T>
T storedValue(double value, std::uint64_t& clamped) {
    if (!std::isfinite(value)) {
        ++clamped;
        return T(0);
    }
    if constexpr (std::is_floating_point_v<T>) {
        const double largest = double(std::numeric_limits<T>::max());
        if (std::abs(value) > largest) ++clamped;
        return T(std::clamp(value, -largest, largest));
    } else {
        const double lowest = double(std::numeric_limits<T>::lowest());
        const double highest = double(std::numeric_limits<T>::max());
        const double rounded = std::nearbyint(value);
        if (rounded < lowest || rounded > highest) ++clamped;
        return T(std::clamp(rounded, lowest, highest));
    }
}

template <typename T>
std::uint64_t copyScaled(const FloatVolume& volume, const NiftiStorage& storage, T* out) {
    std::uint64_t clamped = 0;
    for (std::size_t n = 0; n < volume.values.size(); ++n) {
        out[n] = storedValue<T>((double(volume.values[n]) - storage.intercept) / storage.slope, clamped);
    }
    return clamped;
}

std::uint64_t copySamples(const FloatVolume& volume, const NiftiStorage& storage, nifti_image& image) {
    if (volume.channels == 1) {
        image.scl_slope = float(storage.slope);
        image.scl_inter = float(storage.intercept);
        return dispatchSampleType(storage.type, [&](auto sample) {
            return copyScaled(volume, storage, static_cast<decltype(sample)*>(image.data));
        });
    }
    NiftiStorage colour;  // RGB24: bytes, unscaled
    colour.type = SampleType::UInt8;
    return copyScaled(volume, colour, static_cast<std::uint8_t*>(image.data));
}

/// OpenVDB's row-vector matrix (world = index * M) as NIfTI's column form.
void setGeometry(const openvdb::math::Mat4d& worldFromIndex, const NiftiCodes& codes, nifti_image& image) {
    nifti_dmat44 xyz{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) xyz.m[r][c] = worldFromIndex(c, r);
    }
    xyz.m[3][3] = 1.0;
    image.sform_code = codes.sform;
    image.sto_xyz = xyz;
    image.sto_ijk = nifti_dmat44_inverse(xyz);
    double dx, dy, dz;
    nifti_dmat44_to_quatern(xyz, &image.quatern_b, &image.quatern_c, &image.quatern_d, &image.qoffset_x,
                            &image.qoffset_y, &image.qoffset_z, &dx, &dy, &dz, &image.qfac);
    image.qform_code = codes.qform;
    image.qto_xyz = nifti_quatern_to_dmat44(image.quatern_b, image.quatern_c, image.quatern_d, image.qoffset_x,
                                            image.qoffset_y, image.qoffset_z, dx, dy, dz, image.qfac);
    image.qto_ijk = nifti_dmat44_inverse(image.qto_xyz);
    image.dx = image.pixdim[1] = dx;
    image.dy = image.pixdim[2] = dy;
    image.dz = image.pixdim[3] = dz;
    image.xyz_units = NIFTI_UNITS_MM;  // gvr's world is in millimetres whatever the source said
    image.time_units = XYZT_TO_TIME(codes.xyztUnits);
}

bool isNiftiCode(int code) { return code >= NIFTI_XFORM_UNKNOWN && code <= NIFTI_XFORM_MNI_152; }

}  // namespace

NiftiStorage niftiStorageLike(const VolumeMetadata& source, bool float32) {
    NiftiStorage storage;
    if (source.niftiCodes && isNiftiCode(source.niftiCodes->sform) && isNiftiCode(source.niftiCodes->qform)) {
        storage.codes = *source.niftiCodes;
    }
    if (float32 || source.channels != 1) return storage;
    SampleType type = SampleType::Float32;
    try {
        type = sampleTypeFromName(source.sourceType, "");
    } catch (const InputError&) {
        storage.float32Reason = "the source's sample type \"" + source.sourceType + "\" is unknown";
        return storage;
    }
    if (type == SampleType::Float64) {
        storage.float32Reason = "the source was float64";
        return storage;
    }
    if (!std::isfinite(source.storedSlope) || source.storedSlope == 0.0 || !std::isfinite(source.storedIntercept)) {
        storage.float32Reason = "the source's value scaling is not usable";
        return storage;
    }
    storage.type = type;
    if (type != SampleType::Float32) {
        storage.slope = source.storedSlope;
        storage.intercept = source.storedIntercept;
    }
    return storage;
}

std::uint64_t writeNifti(const std::string& path, const FloatVolume& volume, const NiftiStorage& storage) {
    if (volume.channels != 1 && volume.channels != 3) {
        throw InputError(path, "NIfTI output takes 1 or 3 channels, not " + std::to_string(volume.channels));
    }
    const std::int64_t dims[8] = {3, volume.dims.x(), volume.dims.y(), volume.dims.z(), 1, 1, 1, 1};
    NiftiImagePtr image(
        nifti_make_new_nim(dims, volume.channels == 1 ? niftiDatatype(storage.type) : NIFTI_TYPE_RGB24, 1));
    if (!image) throw InputError(path, "nifticlib could not allocate the image");
    image->nifti_type = NIFTI_FTYPE_NIFTI1_1;
    const std::uint64_t clamped = copySamples(volume, storage, *image);
    setGeometry(volume.worldFromIndex, storage.codes, *image);
    nifti_set_debug_level(0);  // its messages would add lines to gvr's one-line errors
    writeAtomically(path, [&](const std::string& temporary) {
        if (nifti_set_filenames(image.get(), temporary.c_str(), 0, 1) != 0) {
            throw InputError(path, "nifticlib does not accept this file name (use .nii or .nii.gz)");
        }
        nifti_image_write(image.get());
        // nifti_image_write reports failures only on stderr (a full disk, ulimit -f),
        // so read the file back: a cut one does not load.
        nifti_image* written = nifti_image_read(temporary.c_str(), /*read_data=*/1);
        if (!written) throw InputError(path, "writing the NIfTI file failed (disk full or file size limit?)");
        nifti_image_free(written);
    });
    return clamped;
}

}  // namespace gvr
