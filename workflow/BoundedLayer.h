/// @file BoundedLayer.h
/// @brief `gvr fit --max-error`: the residual layer that brings a fitted asset to
/// within a bound of its source on every voxel.
#pragma once

#include "pipeline/FloatVolume.h"
#include "pipeline/Progress.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace gvr {

/// The Gaussians' ratio under a bound when none is asked: a coarse preview. The layer
/// costs more bytes than the Gaussians save it above this share (on ch2, the chest,
/// ct-head and norm.mgz, a 40:1 preview gave larger assets than a 400:1 one; see
/// docs/benchmarks.md, "An error bound").
constexpr double kBoundedPreviewRatio = 400.0;

struct BoundedLayerReport {
    double bound = 0.0;          ///< in the source's units
    bool integers = false;       ///< coded in the source's stored samples
    double maxError = 0.0;       ///< measured on the decoded reconstruction, every voxel
    std::size_t exactVoxels = 0; ///< stored exactly: the prediction could not reach them
    std::uint64_t gaussianBytes = 0, fileBytes = 0;
    double seconds = 0.0;
};

/// A bound from `--max-error` text: a number in the source's units, or a
/// percentage of @a dataRange ("0.5%"). @throw InputError naming `max_error`.
double parseMaxError(const std::string& text, double dataRange);

/// Refuses, before any fit, a bound that is no bound at all (NaN, negative or
/// infinite). @throw InputError naming @a name (the flag or argument).
void checkBoundBeforeFit(double bound, const std::string& name);

/// @a assetBytes (a format-2 asset, as the fit wrote it) with a residual layer that
/// takes its Gaussians to within @a bound of @a source (the volume the fit read, as
/// read: every voxel) on every voxel; @a report says what it cost.
/// @throw InputError naming @a name when the source is not on the asset's lattice.
std::string addErrorBound(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                          double bound, BoundedLayerReport& report, const ProgressFn& progress = {});

}  // namespace gvr
