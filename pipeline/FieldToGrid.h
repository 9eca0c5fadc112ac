/// @file FieldToGrid.h
/// @brief Samples a Gaussian field at the voxel centres of a lattice into a sparse
/// grid in physical units: the reconstruction that `gvr export` writes.
#pragma once

#include "GaussianField.h"
#include "Progress.h"
#include "ValueMapping.h"

#include <openvdb/openvdb.h>

#include <optional>

namespace gvr {

/// Where to sample: the voxel centres of @a box, placed in the world (mm) by
/// @a worldFromIndex (OpenVDB's row-vector convention).
struct Lattice {
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
    openvdb::CoordBBox box;
};

/// The source's own lattice: voxels (0, 0, 0) to dims - 1.
Lattice sourceLattice(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims);

/// The source's extent (its voxel cells, edge to edge) covered by voxels of
/// @a voxelSizeMm along each of the source's index axes, starting at its corner.
/// Axes keep their direction, so oblique and sheared volumes stay aligned.
/// @throw InputError when the voxel size is not positive or would need more than
///        2^31 voxels along an axis.
Lattice resizedLattice(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims,
                       double voxelSizeMm);

/// The voxel size that puts @a samples voxels along the source's longest axis (in mm).
double voxelSizeForResolution(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims,
                              int samples);

struct FieldToGridSettings {
    ValueMapping mapping;  ///< the field's normalised values to physical units
    /// Voxels whose physical value (luminance for RGB) is at or below this stay
    /// inactive. Voxels that no Gaussian reaches are inactive in any case.
    std::optional<double> threshold;
};

/// Evaluates @a field (which lives in the index space that @a fieldWorldFromIndex
/// places in the world) at every voxel centre of @a lattice. Work runs in parallel
/// over leaf nodes; each leaf asks the field's BVH once for the Gaussians that
/// reach it, then adds them up voxel by voxel in index order, so a voxel holds
/// exactly what GaussianField::evaluate gives at the same point.
/// @return a float grid named "density" (one channel) or a Vec3s grid named
///         "color" (three), transform = lattice.worldFromIndex. Inactive voxels hold
///         the background, the physical value of normalised 0.
openvdb::GridBase::Ptr fieldToGrid(const GaussianField& field, const openvdb::math::Mat4d& fieldWorldFromIndex,
                                   const Lattice& lattice, const FieldToGridSettings& settings,
                                   const ProgressFn& progress = {});

}  // namespace gvr
