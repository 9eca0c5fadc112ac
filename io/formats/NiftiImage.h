/// @file NiftiImage.h
/// @brief A nifticlib image owned by a unique_ptr, for the NIfTI reader and writer.
#pragma once

#include <nifti2_io.h>

#include <memory>

namespace gvr {

struct NiftiImageDeleter {
    void operator()(nifti_image* image) const { nifti_image_free(image); }
};
using NiftiImagePtr = std::unique_ptr<nifti_image, NiftiImageDeleter>;

}  // namespace gvr
