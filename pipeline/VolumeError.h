/// @file VolumeError.h
/// @brief Dense error of a Gaussian field against its volume, every voxel counted.
#pragma once

#include "GaussianField.h"
#include "Progress.h"
#include "VolumeTarget.h"

#include <functional>

namespace gvr {

struct VolumeError {
    double mse = 0.0;            ///< over every voxel of the box, normalised units
    double foregroundMse = 0.0;  ///< over the active voxels only (above the ingest threshold)
    std::uint64_t voxels = 0, foregroundVoxels = 0;
    double psnr = 0.0, foregroundPsnr = 0.0;  ///< dB, peak = target.peak()
    /// The same over the voxels that the marking given to measureVolumeError()
    /// picks (brick seams, say) and over the rest; zero without a marking.
    std::uint64_t markedVoxels = 0;
    double markedMse = 0.0, unmarkedMse = 0.0;
    double markedPsnr = 0.0, unmarkedPsnr = 0.0;
};

/// Picks voxels whose error is also summed on its own.
using VoxelMarking = std::function<bool(const openvdb::Coord&)>;

/// Evaluates the field at every voxel centre of target.box(), in parallel over
/// z-slices; the result does not depend on the thread count.
VolumeError measureVolumeError(const GaussianField& field, const VolumeTarget& target,
                               const ProgressFn& progress = {}, const VoxelMarking& marked = {});

}  // namespace gvr
