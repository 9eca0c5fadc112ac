/// @file StackGeometry.h
/// @brief Where a slice stack's samples lie: slices perpendicular to a direction
/// through the volume, placed on its voxel centres where they can be.
#pragma once

#include "pipeline/LatticeSampler.h"
#include "render/RenderVolume.h"

#include <openvdb/math/Vec2.h>

namespace gvr {

struct StackGeometry {
    openvdb::Vec3d normal, e1, e2;      ///< unit, world; slices are perpendicular to normal
    openvdb::Vec3d origin;              ///< world position of sample (0, 0) of slice 0, the front
    openvdb::Vec2d sampleMm{1.0, 1.0};  ///< between samples along e1 and along e2
    double sliceMm = 1.0;               ///< between slices
    /// sliceMm in voxels (RenderVolume::voxelMm): the spacing asked, or when that is
    /// coarser, the finest that can show more (kMostSamplesPerVoxelCrossed slices for
    /// each voxel a ray can cross).
    double sliceVoxels = 1.0;
    int width = 0, height = 0, slices = 0;
    /// The volume's extent along e2, in rows of samples (fractional): its faces,
    /// when e2 runs along one of its axes. Nothing lies beyond them, though the
    /// lattice reaches a row further (of background, for resampling up to them).
    double firstRowInside = 0.0, lastRowInside = 0.0;
    /// The same along e1, in columns.
    double firstColumnInside = 0.0, lastColumnInside = 0.0;
    /// Whether the samples of a slice fall on the volume's voxel centres (and evenly
    /// between them) along e1 and e2.
    bool samplesOnVoxels = false;

    /// The sample lattice: index (i, j, k) is sample (i, j) of slice k.
    Lattice lattice() const;
};

/// The lattice of slices perpendicular to @a direction that covers the volume,
/// @a sliceSpacingVoxels apart (a voxel is the volume's smallest voxel edge), or
/// as far apart as the volume's finest spacing along it when that is further, and
/// about @a sampleMm across (at sampleSpacing when @a fine): on the voxel centres
/// nearby for a stack of values, whose bilinear resampling is then the trilinear
/// field. Not for classified samples: there resampling blends colours classified
/// at the voxels, not the colour of blended voxels, and at `gvr render`'s default
/// view axis frames of the colour cryosection scored lower against the reference
/// on the voxel centres than off them (docs/benchmarks.md, "Stacks of colours").
StackGeometry stackGeometryFor(const RenderVolume& volume, const openvdb::Vec3d& direction, double sliceSpacingVoxels,
                               double sampleMm, bool keepsValues, bool fine);

/// How far, in samples across and down, a view within @a maxAngleDeg of a stack's
/// normal (up to 80 degrees) shears from one slice to the next.
int segmentReach(const StackGeometry& g, double maxAngleDeg);

}  // namespace gvr
