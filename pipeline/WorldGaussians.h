/// @file WorldGaussians.h
/// @brief An asset's Gaussians in the world: millimetres and physical units, as
/// someone outside gvr (numpy, a point-cloud tool) expects them.
#pragma once

#include "pipeline/GaussianAsset.h"

#include <array>
#include <vector>

namespace gvr {

/// One Gaussian of the field f(x) = background + sum amplitude * exp(-x^T S^-1 x / 2),
/// S = R diag(scale^2) R^T, all in the world.
struct WorldGaussian {
    std::array<double, 3> mean;       ///< world millimetres
    std::array<double, 3> scale;      ///< standard deviations along its axes, mm, ascending
    std::array<double, 4> rotation;   ///< unit quaternion (w, x, y, z), w >= 0: its axes as R's columns
    std::array<double, 3> amplitude;  ///< peak over the background, physical units (HU...); channels used
};

/// The asset's Gaussians, in its order. The voxel spacing and any shear of the
/// source shape each one's world covariance, so world scales and rotations come
/// from that covariance, not from the stored index-space ones.
std::vector<WorldGaussian> worldGaussians(const GaussianAsset& asset);

}  // namespace gvr
