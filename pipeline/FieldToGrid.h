/// @file FieldToGrid.h
/// @brief Samples a Gaussian field at the voxel centres of a lattice into a sparse
/// grid in physical units: the reconstruction that `gvr export` writes.
#pragma once

#include "pipeline/LatticeSampler.h"
#include "pipeline/Progress.h"
#include "pipeline/ValueMapping.h"

#include <openvdb/openvdb.h>

#include <optional>

namespace gvr {

struct FieldToGridSettings {
    ValueMapping mapping;  ///< the field's normalised values to physical units
    /// Voxels whose physical value (luminance for RGB) is at or below this stay
    /// inactive. Voxels that no Gaussian reaches are inactive in any case.
    std::optional<double> threshold;
    std::optional<double> thresholdAbove;  ///< and those at or above this
    /// The field's source voxels: lattice points outside their cells stay background
    /// (default: no limit).
    openvdb::CoordBBox fieldBox = openvdb::CoordBBox::inf();
    /// exact for export (the very floats of GaussianField::evaluate); rows for the
    /// renderer, several times faster and within 1e-6 of each Gaussian's peak.
    BlockEvaluation evaluation = BlockEvaluation::Exact;
};

/// Evaluates @a field (which lives in the index space that @a fieldWorldFromIndex
/// places in the world) at every voxel centre of @a lattice, in parallel over leaf
/// nodes through a LatticeSampler (exactly what GaussianField::evaluate gives, unless
/// settings.evaluation says otherwise).
/// @return a float grid named "density" (one channel) or a Vec3s grid named
///         "color" (three), transform = lattice.worldFromIndex. Inactive voxels hold
///         the background, the physical value of normalised 0.
openvdb::GridBase::Ptr fieldToGrid(const GaussianField& field, const openvdb::math::Mat4d& fieldWorldFromIndex,
                                   const Lattice& lattice, const FieldToGridSettings& settings,
                                   const ProgressFn& progress = {});

}  // namespace gvr
