/// @file FieldAccuracy.h
/// @brief How well a Gaussian field reproduces its volume: the dense error, every
/// voxel counted.
#pragma once

#include "pipeline/GaussianField.h"
#include "pipeline/Progress.h"
#include "pipeline/ThresholdCut.h"
#include "pipeline/VolumeTarget.h"

#include <functional>
#include <vector>

namespace gvr {

/// MSE and PSNR of a field against its volume, whole and in parts.
struct FieldAccuracy {
    double mse = 0.0;            ///< over every voxel of the box, normalised units
    double foregroundMse = 0.0;  ///< over the active voxels only (above the ingest threshold)
    std::uint64_t voxels = 0, foregroundVoxels = 0;
    double psnr = 0.0, foregroundPsnr = 0.0;  ///< dB, peak = target.peak()
    /// The same over the voxels that the marking given to measureFieldAccuracy()
    /// picks (brick seams, say) and over the rest; zero without a marking.
    std::uint64_t markedVoxels = 0;
    double markedMse = 0.0, unmarkedMse = 0.0;
    double markedPsnr = 0.0, unmarkedPsnr = 0.0;
    /// The same split of the active voxels only: what the volume holds, without the
    /// background, which is easy to fit and not spread evenly over the marked voxels.
    std::uint64_t markedForegroundVoxels = 0;
    double markedForegroundPsnr = 0.0, unmarkedForegroundPsnr = 0.0;
};

/// Picks voxels whose error is also summed on its own.
using VoxelMarking = std::function<bool(const openvdb::Coord&)>;

/// One z-slice's squared errors (channel mean) and voxel counts. Plain doubles, so
/// that processes that measure different slices can send them as they are.
struct SliceSums {
    double all = 0.0, foreground = 0.0, marked = 0.0, markedForeground = 0.0;
    double foregroundVoxels = 0.0, markedVoxels = 0.0, markedForegroundVoxels = 0.0;  // counts, exact in a double

    void add(const SliceSums& other);
};

/// Evaluates the field at every voxel centre of target.box(), in parallel over
/// z-slices, and applies @a cut as export does; the result does not depend on
/// the thread count.
FieldAccuracy measureFieldAccuracy(const GaussianField& field, const VolumeTarget& target,
                                   const ProgressFn& progress = {}, const VoxelMarking& marked = {},
                                   const ThresholdCut& cut = {});

/// About how long measureFieldAccuracy() takes on @a field: the same work timed
/// over every @a stride-th block of target.box(), scaled up. A fit with a time
/// budget keeps this much for the measurement that follows it.
double estimateMeasurementSeconds(const GaussianField& field, const VolumeTarget& target, std::size_t stride = 61);

/// The part of measureFieldAccuracy() inside @a part (clipped to target.box()): one
/// entry per z-slice of the clipped part, lowest z first, for a measurement shared
/// out by region (an MPI rank's bricks, say).
std::vector<SliceSums> measureSliceSums(const GaussianField& field, const VolumeTarget& target, openvdb::CoordBBox part,
                                        const ProgressFn& progress = {}, const VoxelMarking& marked = {},
                                        const ThresholdCut& cut = {});

/// The error of the whole box from the sums of each of its z-slices, lowest first.
FieldAccuracy fieldAccuracyOf(const std::vector<SliceSums>& slices, const VolumeTarget& target);

}  // namespace gvr
