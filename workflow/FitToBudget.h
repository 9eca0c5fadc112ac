/// @file Compress.h
/// @brief A volume in, a Gaussian asset out: the fit sized to a compression ratio
/// or a count, with its byte budget kept, as `gvr fit` runs it.
#pragma once

#include "io/asset/AssetFile.h"
#include "pipeline/Fitter.h"
#include "pipeline/LabelledFit.h"

#include <openvdb/openvdb.h>

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace gvr {

/// The time budget `gvr fit` and Python's `gvr.fit` take when none is given.
constexpr double kDefaultFitSeconds = 300.0;

/// Voxel samples a Gaussian below which a fit is reported as undertrained: at a
/// fixed time, quality peaked a little above this on `ch2`.
constexpr double kTrainedSamplesPerGaussian = 1000.0;

struct BudgetedFitOptions {
    /// Against the source's raw bytes (VolumeMetadata::rawSourceBytes); the count
    /// is what fits in rawBytes / ratio. Ignored when @a gaussians is set.
    double ratio = 10.0;
    std::size_t gaussians = 0;  ///< an exact count instead (the time then never lowers it)
    /// With a ratio: at least this many, past the ratio's bytes where they hold fewer
    /// (a bound's preview of a small volume, whose 400:1 leaves no room past the header).
    std::size_t minimumGaussians = 0;
    /// Time or iterations must be set. The count (settings.gaussians) is derived;
    /// the ablation (applyAblation) is recorded in the asset as @a ablation.
    FitSettings settings;
    std::string ablation = "full";
    AssetEncoding encoding;
    /// Structures to fit one by one from a label grid ("all", or ids and names,
    /// comma-separated); empty: the whole volume.
    std::string labels;
    /// Set it (from any thread) to stop the fit at its next iteration; fitToBudget()
    /// then throws Cancelled. Null: the fit runs to its budget.
    const std::atomic<bool>* cancel = nullptr;
};

struct BudgetedFitResult {
    GaussianAsset asset;                   ///< within the byte budget, in storage order
    std::string file;                      ///< the asset coded: writeAssetBytes() it
    FitReport fit;                         ///< summed over the structures of a labelled fit
    std::uint64_t maxBytes = 0;            ///< the byte budget; 0 when a count was asked for
    std::size_t dropped = 0;               ///< Gaussians dropped so that the file fits the budget
    std::vector<StructureFit> structures;  ///< one per structure of a labelled fit
};

/// The voxel samples the fit gave each Gaussian of the asset, on average (0 for none).
double samplesPerGaussian(const BudgetedFitResult& result);

/// When a time budget gave the fit's Gaussians fewer than kTrainedSamplesPerGaussian
/// voxel samples each: one line saying so, with the budget that would have, and
/// @a tradeOption, the option that trades Gaussians for training ("--min-samples",
/// or "min_samples=" where the value follows without a space). Else empty.
std::string undertrainedNote(const BudgetedFitResult& result, const FitSettings& settings,
                             const std::string& tradeOption);

/// The fit settings fitToBudget() uses: the ablation applied, and no ceiling on the
/// count when an exact count was asked for. Cheap: callers check options with it
/// before reading a volume.
/// @throw InputError naming "fit settings" when FitSettings::validate() refuses them.
FitSettings checkedSettings(const BudgetedFitOptions& options);

/// The asset of a fit of @a target with everything but the Gaussians: placement,
/// value mapping, source record, settings and encoding.
GaussianAsset assetSkeleton(const VolumeTarget& target, const FitSettings& settings, const BudgetedFitOptions& options,
                            const std::string& name);

/// The whole volume's count for @a asset (a skeleton): options.gaussians, or what
/// fits the ratio's byte budget, which goes to @a maxBytes (0 for an exact count).
/// @throw InputError for a ratio below 1 or too high for one Gaussian.
std::size_t budgetedGaussians(const GaussianAsset& asset, const BudgetedFitOptions& options, std::uint64_t& maxBytes);

/// FitSettings::roomInBudget for Gaussians stored with @a skeleton in @a maxBytes:
/// what 99 % of it still holds, since the training after the last fill makes the
/// Gaussians code a little larger and the writer drops the weakest that no longer fit.
std::function<std::size_t(const GaussianParameters&)> roomInBytes(const GaussianAsset& skeleton,
                                                                  std::uint64_t maxBytes);

/// Fits @a grid (an ingested volume, or any float or Vec3s grid) and returns the
/// asset. @a name names the volume in errors and, for a grid that gvr did not
/// ingest, in the asset's source record. @a labels: the label grid that
/// `ingest --labels` stored beside the image, needed when options.labels is set.
/// An empty grid gives an empty asset.
/// @throw InputError for settings that validate() refuses, a ratio below 1 or too
///        high for one Gaussian, or labels asked for without a label grid;
///        Cancelled once options.cancel is set.
BudgetedFitResult fitToBudget(const openvdb::GridBase::Ptr& grid, const std::string& name,
                              const BudgetedFitOptions& options, const FitObserver& observer = {},
                              const openvdb::Int32Grid* labels = nullptr);

/// The same, for a caller that holds the grid's VolumeTarget already (to measure the
/// result against it, say): the target's grid is fitted.
BudgetedFitResult fitToBudget(const VolumeTarget& target, const std::string& name, const BudgetedFitOptions& options,
                              const FitObserver& observer = {}, const openvdb::Int32Grid* labels = nullptr);

}  // namespace gvr
