#include "workflow/FitToBudget.h"

#include "io/LabelGrid.h"
#include "pipeline/Error.h"
#include "pipeline/LabelBudget.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace gvr {

namespace {

/// The settings as the asset records them, with the names of `gvr fit`'s flags.
nlohmann::json settingsJson(const FitSettings& s, const std::string& ablation) {
    return {{"ablation", ablation},
            {"seed", s.seed},
            {"iterations", s.iterations},
            {"seconds", s.seconds},
            {"batch", s.voxelBatch},
            {"refresh_every", s.refreshEvery},
            {"row_stride", s.rowStride},
            {"rebin_every", s.rebinEvery},
            {"min_samples", s.minSamplesPerGaussian},
            {"mc_lambda", s.importance.uniformShare},
            {"mc_epsilon", s.importance.epsilon},
            {"slice_pixels", s.slicePixels},
            {"slice_max", s.sliceMax},
            {"slice_gamma", s.sliceGamma},
            {"slice_beta", s.sliceBeta},
            {"lr", s.learningRate},
            {"lr_final", s.finalRateFactor},
            {"gradient_share", s.gradientSeedShare},
            {"uniform_share", s.uniformSeedShare},
            {"prune_every", s.pruneEvery},
            {"prune_amplitude", s.pruneAmplitude},
            {"solve_iterations", s.amplitudeSolveIterations},
            {"solve_share", s.amplitudeSolveShare}};
}

void checkRatio(double ratio) {
    if (!(ratio >= 1.0) || !std::isfinite(ratio)) throw InputError("`ratio`", "must be at least 1");
}

}  // namespace

GaussianAsset assetSkeleton(const VolumeTarget& target, const FitSettings& settings, const BudgetedFitOptions& options,
                            const std::string& name) {
    const openvdb::GridBase& grid = target.grid();
    GaussianAsset asset;
    asset.params = GaussianParameters(0, target.channels());
    asset.cutoffSigmas = settings.cutoffSigmas;
    asset.worldFromIndex = grid.transform().baseMap()->getAffineMap()->getMat4();
    asset.mapping = target.mapping();
    if (auto metadata = readVolumeMetadata(grid)) {
        asset.source = *metadata;
    } else {  // a foreign grid: describe it as float32 samples over its box
        asset.source.sourceFile = name;
        asset.source.sourceType = "float32";
        asset.source.channels = target.channels();
        asset.source.dims = openvdb::Vec3i(target.box().dim().asVec3i());
        asset.source.spacingMm = grid.transform().voxelSize();
    }
    asset.fitSettings = settingsJson(settings, options.ablation);
    asset.encoding = options.encoding;
    return asset;
}

std::function<std::size_t(const GaussianParameters&)> roomInBytes(const GaussianAsset& skeleton,
                                                                  std::uint64_t maxBytes) {
    return [skeleton, maxBytes](const GaussianParameters& params) {
        GaussianAsset now = skeleton;
        now.params = params;
        return assetRoom(now, std::uint64_t(0.99 * double(maxBytes)));
    };
}

std::size_t budgetedGaussians(const GaussianAsset& asset, const BudgetedFitOptions& options, std::uint64_t& maxBytes) {
    maxBytes = 0;
    if (options.gaussians > 0) return options.gaussians;
    checkRatio(options.ratio);
    maxBytes = std::uint64_t(double(asset.source.rawSourceBytes()) / options.ratio);
    const std::size_t capacity = assetCapacity(asset, maxBytes);
    if (capacity < options.minimumGaussians) {
        maxBytes = 0;  // a count, as if asked for
        return options.minimumGaussians;
    }
    if (capacity == 0) {
        throw InputError("`ratio`", "leaves " + std::to_string(maxBytes) + " bytes, too few for even one Gaussian");
    }
    return capacity;
}

namespace {

/// Gaussians per structure: the count split with a floor, or the ratio applied to
/// each structure's own raw bytes.
std::vector<std::size_t> structureBudgets(const BudgetedFitOptions& options, const GaussianAsset& asset,
                                          const std::vector<std::uint64_t>& voxels) {
    if (options.gaussians > 0) return splitBudget(options.gaussians, voxels);
    checkRatio(options.ratio);
    const double sourceVoxels = double(asset.source.dims.x()) * asset.source.dims.y() * asset.source.dims.z();
    const double rawBytesPerVoxel = double(asset.source.rawSourceBytes()) / sourceVoxels;
    const double wholeVolumeBytes = double(asset.source.rawSourceBytes()) / options.ratio;
    const double perGaussian =
        assetEstimatedBytesPerGaussian(asset, double(assetCapacity(asset, std::uint64_t(wholeVolumeBytes))));
    return proportionalBudgets(rawBytesPerVoxel / options.ratio / perGaussian, voxels);
}

/// Fits the structures that options.labels names into @a result.
void fitByLabel(const openvdb::GridBase& image, const openvdb::Int32Grid& labels, const FitSettings& settings,
                const BudgetedFitOptions& options, const FitObserver& observer, BudgetedFitResult& result) {
    GaussianAsset& asset = result.asset;
    const LabelTable table = labelTableOf(labels);
    const std::vector<int> ids = selectLabels(table, options.labels, "`labels`");
    const std::vector<std::uint64_t> voxels = countLabelVoxels(labels, ids);
    const std::vector<std::size_t> budgets = structureBudgets(options, asset, voxels);
    std::vector<StructureFit> structures;
    for (std::size_t s = 0; s < ids.size(); ++s) {
        structures.push_back({ids[s], voxels[s], budgets[s], {}});
        asset.labelTable.names[ids[s]] = table.nameOf(ids[s]);
    }
    LabelledFitResult fitted = fitStructures(image, labels, structures, settings, observer);
    asset.params = std::move(fitted.params);
    asset.labels = std::move(fitted.labels);
    FitReport& total = result.fit;
    for (const StructureFit& s : fitted.structures) {
        total.iterations += s.report.iterations;
        total.seconds += s.report.seconds;
        total.skippedSteps += s.report.skippedSteps;
        total.pruned += s.report.pruned;
        total.voxelSamples += s.report.voxelSamples;
        total.setupSeconds += s.report.setupSeconds;
        total.adamSeconds += s.report.adamSeconds;
        total.respawned += s.report.respawned;
        // Per-structure errors cover overlapping boxes: only the work adds up.
        total.amplitudeSolve.iterations += s.report.amplitudeSolve.iterations;
        total.amplitudeSolve.seconds += s.report.amplitudeSolve.seconds;
    }
    result.structures = std::move(fitted.structures);
}

/// @a observer, after a check of the cancel flag at every iteration.
FitObserver cancellable(const FitObserver& observer, const std::atomic<bool>* cancel, const std::string& name) {
    if (!cancel) return observer;
    return [observer, cancel, name](const FitProgress& progress) {
        if (cancel->load()) throw Cancelled(name);
        if (observer) observer(progress);
    };
}

}  // namespace

double samplesPerGaussian(const BudgetedFitResult& result) {
    const std::size_t count = result.asset.params.count();
    return count ? result.fit.voxelSamples / double(count) : 0.0;
}

std::string undertrainedNote(const BudgetedFitResult& result, const FitSettings& settings,
                             const std::string& tradeOption) {
    const std::size_t count = result.asset.params.count();
    const FitReport& fit = result.fit;
    if (!(settings.seconds > 0.0) || count == 0) return "";
    std::ostringstream note;
    if (fit.iterations == 0) {  // no iteration to time: only the set-up's cost is known
        note << std::fixed << std::setprecision(1) << "undertrained: the " << settings.seconds
             << " s budget ended before the first iteration, the set-up alone taking " << fit.setupSeconds << " s; the "
             << count << " Gaussians are as seeded";
        return note.str();
    }
    const double perGaussian = samplesPerGaussian(result);
    if (perGaussian >= kTrainedSamplesPerGaussian) return "";
    // Only the iterations' time grows with the samples; set-up, solve and measurement stay.
    const double iterationSeconds = std::max(fit.adamSeconds - fit.setupSeconds, 0.0);
    const double needed =
        settings.seconds + iterationSeconds * (kTrainedSamplesPerGaussian / std::max(perGaussian, 1.0) - 1.0);
    note << "undertrained: " << std::llround(settings.seconds) << " s gave each of the " << count << " Gaussians about "
         << std::llround(perGaussian) << " voxel samples; about " << std::llround(std::ceil(needed / 10.0) * 10.0)
         << " s would give each " << std::llround(kTrainedSamplesPerGaussian) << " (" << tradeOption
         << (!tradeOption.empty() && tradeOption.back() == '=' ? "" : " ") << std::llround(kTrainedSamplesPerGaussian)
         << " fits fewer Gaussians in this time instead, above the ratio)";
    return note.str();
}

FitSettings checkedSettings(const BudgetedFitOptions& options) {
    FitSettings settings = options.settings;
    applyAblation(ablationFromName(options.ablation), settings);
    if (options.gaussians > 0) settings.minSamplesPerGaussian = 0.0;
    const std::string problem = settings.validate();
    if (!problem.empty()) throw InputError("fit settings", problem);
    return settings;
}

BudgetedFitResult fitToBudget(const openvdb::GridBase::Ptr& grid, const std::string& name,
                              const BudgetedFitOptions& options, const FitObserver& observer,
                              const openvdb::Int32Grid* labels) {
    checkedSettings(options);  // before the target reads the grid
    return fitToBudget(VolumeTarget(grid, name), name, options, observer, labels);
}

namespace {

/// The Gaussians of the fit into result.asset, not yet coded.
void fitGaussiansInto(const VolumeTarget& target, const BudgetedFitOptions& options, FitSettings settings,
                      const FitObserver& observer, const openvdb::Int32Grid* labels, BudgetedFitResult& result) {
    if (target.activeVoxelCount() == 0) return;
    if (labels && !options.labels.empty()) {
        // Structures are stored together, over ranges and a budget that no single
        // structure knows, so their fits skip the solve on the stored geometry.
        fitByLabel(target.grid(), *labels, settings, options, observer, result);
        return;
    }
    settings.gaussians = budgetedGaussians(result.asset, options, result.maxBytes);
    // The last amplitude solve makes up for what the file does to the geometry: its
    // rounding, and the weakest Gaussians dropped if the estimate of the file size
    // was short.
    settings.storedGeometry = [&](const GaussianParameters& params) {
        GaussianAsset stored = result.asset;
        stored.params = params;
        result.dropped = fitAssetInto(stored, result.maxBytes);
        return quantisedCopy(stored.params, options.encoding);
    };
    if (result.maxBytes > 0) settings.roomInBudget = roomInBytes(result.asset, result.maxBytes);
    result.asset.params = fitGaussians(target, settings, observer, &result.fit);
}

}  // namespace

BudgetedFitResult fitToBudget(const VolumeTarget& target, const std::string& name, const BudgetedFitOptions& options,
                              const FitObserver& userObserver, const openvdb::Int32Grid* labels) {
    const FitSettings settings = checkedSettings(options);
    if (options.cancel && options.cancel->load()) throw Cancelled(name);
    const FitObserver observer = cancellable(userObserver, options.cancel, name);
    if (!options.labels.empty() && !labels)
        throw InputError(name, "holds no label grid; ingest the image with `labels=LABELS`, or give the label volume");

    BudgetedFitResult result;
    result.asset = assetSkeleton(target, settings, options, name);
    fitGaussiansInto(target, options, settings, observer, labels, result);
    // Coded once, for the caller to write: the fit's time budget keeps room for this
    // coding, timed by its checks of the room in the file (FitSettings::roomInBudget).
    const std::size_t fitted = result.asset.params.count();
    result.file = encodeAssetWithin(result.asset, result.maxBytes);
    result.dropped += fitted - result.asset.params.count();
    return result;
}

}  // namespace gvr
