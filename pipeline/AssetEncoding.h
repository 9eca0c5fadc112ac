/// @file AssetEncoding.h
/// @brief How finely a stored asset keeps each attribute of its Gaussians.
///
/// Part of the model, not of one file layout: the fit's last amplitude solve runs on
/// the geometry as these depths round it. io/asset/AssetBodyV2.h turns them into bytes.
#pragma once

namespace gvr {

/// Bit depths and the compression level. The defaults come from measuring each
/// attribute's rate against the reconstruction PSNR (README, "Asset format").
struct AssetEncoding {
    float meanStep = 1.0f / 8.0f;  ///< lattice of the means, in voxels
    int rotationBits = 7;          ///< per stored quaternion component, 2-15
    int logScaleBits = 7;          ///< per axis, 2-16
    int amplitudeBits = 10;        ///< per channel, 2-16
    int zstdLevel = 19;
};

}  // namespace gvr
