/// @file GridBuilder.h
/// @brief Turns a decoded volume into a sparse OpenVDB grid in physical units.
#pragma once

#include "io/DenseVolume.h"
#include "io/formats/SliceSource.h"
#include "pipeline/Progress.h"

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace gvr {

/// The threshold a CT gets when none is given: above air (-1000 HU and its noise),
/// below everything a body holds (lungs are about -890 HU).
constexpr double kCtDefaultThreshold = -950.0;

struct GridBuildSettings {
    std::string sourceFile;  ///< recorded in the metadata and named in errors
    /// Voxels whose value (luminance for RGB) is at or below this are inactive.
    /// Unset: kCtDefaultThreshold for a CT (modality "CT"), else only voxels at the
    /// volume's minimum, e.g. zero padding or air fill; for colour, only when they
    /// are at least 1 % of the volume (a section photographed on paper has a darkest
    /// voxel of its own: nothing is cut, and the background is its faces' median).
    std::optional<double> threshold;
    /// Voxels at or above this (luminance for RGB) are inactive too: the white paper
    /// or bright medium behind a cryosection.
    std::optional<double> thresholdAbove;
    /// Mirrors index axes i, j, k (i -> n - 1 - i) in the world: a stack scanned
    /// upside down or read in another order stands as it should.
    std::array<bool, 3> flip{false, false, false};
    /// Value that replaces NaN and Inf samples. Unset: such samples are an error.
    std::optional<float> nanTo;
    std::string modality;  ///< overrides what the file says, when not empty
    /// Every voxel active, whatever the thresholds: the source as read, for
    /// comparisons that must count what a threshold would lose.
    bool keepEveryVoxel = false;
    /// A streamed build reads about this many bytes of samples at a time (at least
    /// one leaf's 8 slices).
    std::uint64_t slabBytes = 64u << 20;

    /// Checks the values a user gives, the same for every front end: finite
    /// thresholds, the upper above the lower, and a finite float for nanTo.
    /// @throw InputError naming the setting (`threshold`, `threshold_above`, `nan_to`)
    void validate() const;
};

/// Builds a float grid named "density" (grey) or a Vec3s grid named "color" (RGB)
/// whose transform maps index space to world millimetres, with VolumeMetadata
/// attached. Inactive voxels hold the background: the mean of the deactivated
/// voxels (the minimum, or black, when none are).
/// @throw InputError naming the source file for NaN/Inf samples without nanTo, or
///        for a degenerate orientation matrix; as validate() for bad settings.
openvdb::GridBase::Ptr buildGrid(const DenseVolume& volume, const GridBuildSettings& settings,
                                 const ProgressFn& progress = {});

/// The same grid, built from @a source a slab at a time: the dense samples held at
/// any moment are one slab's (settings.slabBytes), whatever the volume's size.
/// @throw InputError as above, and naming the source when a slab no longer fits
///        in the memory that the grid leaves.
openvdb::GridBase::Ptr buildGrid(const SliceSource& source, const GridBuildSettings& settings,
                                 const ProgressFn& progress = {});

}  // namespace gvr
