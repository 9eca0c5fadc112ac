/// @file Initialisation.h
/// @brief One Gaussian per seed voxel: seeds from high gradients and at random.
#pragma once

#include "pipeline/GaussianParameters.h"
#include "pipeline/Progress.h"
#include "pipeline/VolumeTarget.h"

#include <cstdint>

namespace gvr {

struct SeedSettings {
    std::size_t count = 0;       ///< Gaussians wanted (at most the active voxel count)
    double gradientShare = 0.6;  ///< drawn with probability proportional to gradient magnitude
    double uniformShare = 0.4;   ///< drawn uniformly; the two shares are renormalised to sum to 1
    std::uint64_t seed = 1;
};

/// Places Gaussians on distinct active voxels only, never in empty space. Each
/// starts isotropic, with a standard deviation of half the mean distance to its
/// three nearest neighbours, opacity 1/2, and a colour that makes the overlapping
/// Gaussians reproduce the voxel values at the seeds.
GaussianParameters initialiseGaussians(const VolumeTarget& target, const SeedSettings& settings,
                                       const ProgressFn& progress = {});

}  // namespace gvr
