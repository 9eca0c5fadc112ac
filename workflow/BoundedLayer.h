/// @file BoundedLayer.h
/// @brief `gvr fit --max-error`: the residual layer that brings a fitted asset to
/// within a bound of its source on every voxel.
#pragma once

#include "pipeline/FloatVolume.h"
#include "pipeline/Progress.h"
#include "workflow/FitToBudget.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace gvr {

/// The Gaussians' ratio under a bound when none is asked: a coarse preview. The layer
/// costs more bytes than the Gaussians save it above this share (on ch2, the chest,
/// ct-head and norm.mgz, a 40:1 preview gave larger assets than a 400:1 one; see
/// docs/benchmarks.md, "An error bound").
constexpr double kBoundedPreviewRatio = 400.0;

/// A preview has at least this many Gaussians: on a small volume (64 x 64 x 24
/// floats) 400:1 leaves no room past the file's header.
constexpr std::size_t kBoundedPreviewGaussians = 64;

/// What `--max-error` reads as a request to search the bound.
inline constexpr const char* kSearchedBound = "auto";

/// A fit under a bound, as asked.
struct BoundRequest {
    std::string maxError;  ///< a number in the source's units, a percentage of its data range ("0.5%"), or "auto"
    /// The ratio given with it (0: none): with "auto", what the whole asset must fit;
    /// else the Gaussians' (none: kBoundedPreviewRatio).
    double ratio = 0.0;

    /// A request for @a bound itself (its text holds the double exactly).
    static BoundRequest exactly(double bound, double ratio = 0.0);

    bool searched() const { return maxError == kSearchedBound; }
    /// The ratio the Gaussians are fit at: under a searched bound, a quarter of the
    /// whole asset's budget at most, so that the layer has the rest.
    double gaussianRatio() const;
    /// @a options with the Gaussians' budget under this bound (unless they ask a count).
    void applyTo(BudgetedFitOptions& options) const;
};

struct BoundedLayerReport {
    double bound = 0.0;           ///< in the source's units
    bool integers = false;        ///< coded in the source's stored samples
    double maxError = 0.0;        ///< measured on the decoded reconstruction, every voxel
    std::size_t exactVoxels = 0;  ///< stored exactly: the prediction could not reach them
    std::uint64_t gaussianBytes = 0, fileBytes = 0;
    double searchedRatio = 0.0;  ///< the whole asset's ratio a searched bound was fitted to (0: not searched)
    int encodes = 1;             ///< layers encoded to find the bound
    double seconds = 0.0;
};

/// A bound from `--max-error` text: a number in the source's units, or a
/// percentage of @a dataRange ("0.5%"). @throw InputError naming `max_error`.
double parseMaxError(const std::string& text, double dataRange);

/// Refuses, before any fit, a request that is no bound at all (NaN, negative or
/// infinite), or "auto" with no ratio to search for. @throw InputError naming
/// @a maxErrorName or @a ratioName (the flags or arguments).
void checkBoundRequest(const BoundRequest& request, const std::string& maxErrorName, const std::string& ratioName);

/// @a assetBytes (a format-2 asset, as the fit wrote it) with the residual layer
/// @a request asks for, over @a source (the volume the fit read, as read: every
/// voxel): every voxel within the bound, or within the smallest bound with which the
/// whole file fits the request's ratio. @a report says what it cost.
/// @throw InputError naming @a name when the source is not on the asset's lattice, or
///        when not even the largest bound fits the ratio.
std::string addErrorBound(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                          const BoundRequest& request, BoundedLayerReport& report, const ProgressFn& progress = {});

}  // namespace gvr
