#include "NiftiWriter.h"

#include "AtomicFile.h"
#include "Error.h"

#include <nifti2_io.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace gvr {

namespace {

struct NiftiImageDeleter {
    void operator()(nifti_image* image) const { nifti_image_free(image); }
};

void copySamples(const FloatVolume& volume, nifti_image& image) {
    if (volume.channels == 1) {
        std::copy(volume.values.begin(), volume.values.end(), static_cast<float*>(image.data));
        return;
    }
    auto* bytes = static_cast<std::uint8_t*>(image.data);
    for (std::size_t n = 0; n < volume.values.size(); ++n) {
        bytes[n] = std::uint8_t(std::clamp(std::lround(volume.values[n]), 0L, 255L));
    }
}

/// OpenVDB's row-vector matrix (world = index * M) as NIfTI's column form.
void setGeometry(const openvdb::math::Mat4d& worldFromIndex, nifti_image& image) {
    nifti_dmat44 xyz{};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) xyz.m[r][c] = worldFromIndex(c, r);
    }
    xyz.m[3][3] = 1.0;
    image.sform_code = NIFTI_XFORM_SCANNER_ANAT;
    image.sto_xyz = xyz;
    image.sto_ijk = nifti_dmat44_inverse(xyz);
    double dx, dy, dz;
    nifti_dmat44_to_quatern(xyz, &image.quatern_b, &image.quatern_c, &image.quatern_d, &image.qoffset_x,
                            &image.qoffset_y, &image.qoffset_z, &dx, &dy, &dz, &image.qfac);
    image.qform_code = NIFTI_XFORM_SCANNER_ANAT;
    image.qto_xyz = nifti_quatern_to_dmat44(image.quatern_b, image.quatern_c, image.quatern_d, image.qoffset_x,
                                            image.qoffset_y, image.qoffset_z, dx, dy, dz, image.qfac);
    image.qto_ijk = nifti_dmat44_inverse(image.qto_xyz);
    image.dx = image.pixdim[1] = dx;
    image.dy = image.pixdim[2] = dy;
    image.dz = image.pixdim[3] = dz;
    image.xyz_units = NIFTI_UNITS_MM;
}

}  // namespace

void writeNifti(const std::string& path, const FloatVolume& volume) {
    if (volume.channels != 1 && volume.channels != 3) {
        throw InputError(path, "NIfTI output takes 1 or 3 channels, not " + std::to_string(volume.channels));
    }
    const std::int64_t dims[8] = {3, volume.dims.x(), volume.dims.y(), volume.dims.z(), 1, 1, 1, 1};
    std::unique_ptr<nifti_image, NiftiImageDeleter> image(
        nifti_make_new_nim(dims, volume.channels == 1 ? NIFTI_TYPE_FLOAT32 : NIFTI_TYPE_RGB24, 1));
    if (!image) throw InputError(path, "nifticlib could not allocate the image");
    image->nifti_type = NIFTI_FTYPE_NIFTI1_1;
    copySamples(volume, *image);
    setGeometry(volume.worldFromIndex, *image);
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
}

}  // namespace gvr
