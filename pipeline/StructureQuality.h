/// @file StructureQuality.h
/// @brief Quality per labelled structure, like the rows per organ of the paper's
/// Table 1: PSNR over the structure's voxels, and SSIM of the structure cut out.
#pragma once

#include "pipeline/FloatVolume.h"
#include "pipeline/QualityMetrics.h"

#include <vector>

namespace gvr {

struct StructureQuality {
    int id = 0;
    std::size_t voxels = 0;
    double mse = 0.0, psnr = 0.0;
    /// SSIM over the structure's bounding box with every voxel outside the structure
    /// set to 0 in both volumes: the organ-level volume the paper compares.
    double ssim = 0.0;
};

/// @param labels one label per voxel of @a reference (same dims as @a test)
/// @param peak   the PSNR peak and SSIM data range
std::vector<StructureQuality> structureQuality(const FloatVolume& reference, const FloatVolume& test,
                                               const std::vector<int>& labels, const std::vector<int>& ids,
                                               double peak);

}  // namespace gvr
