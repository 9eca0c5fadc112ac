/// @file GridBuilder.h
/// @brief Turns a decoded volume into a sparse OpenVDB grid in physical units.
#pragma once

#include "DenseVolume.h"
#include "Progress.h"

#include <openvdb/openvdb.h>

#include <optional>
#include <string>

namespace gvr {

struct GridBuildSettings {
    std::string sourceFile;  ///< recorded in the metadata and named in errors
    /// Voxels whose value (luminance for RGB) is at or below this are inactive.
    /// Unset: only voxels at the volume's minimum are, e.g. zero padding or air fill.
    std::optional<double> threshold;
    /// Value that replaces NaN and Inf samples. Unset: such samples are an error.
    std::optional<float> nanTo;
    std::string modality;  ///< overrides what the file says, when not empty
};

/// Builds a float grid named "density" (grey) or a Vec3s grid named "color" (RGB)
/// whose transform maps index space to world millimetres, with VolumeMetadata
/// attached. Inactive voxels hold the background: the mean of the deactivated
/// voxels (the minimum, or black, when none are).
/// @throw InputError naming the source file for NaN/Inf samples without nanTo, or
///        for a degenerate orientation matrix.
openvdb::GridBase::Ptr buildGrid(const DenseVolume& volume, const GridBuildSettings& settings,
                                 const ProgressFn& progress = {});

}  // namespace gvr
