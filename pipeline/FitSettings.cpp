#include "pipeline/FitSettings.h"

#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>

namespace gvr {

std::string FitSettings::validate() const {
    if (iterations == 0 && !(seconds > 0.0)) return "`iterations` or `time` must be positive";
    if (!(seconds >= 0.0 && seconds <= kMaxFitSeconds)) {
        return "`time` must lie in [0, " + std::to_string(std::int64_t(kMaxFitSeconds)) + "] seconds (about 11 days)";
    }
    if (iterations > kMaxFitIterations) {
        return "`iterations` must be at most " + std::to_string(kMaxFitIterations);
    }
    if (voxelBatch > kMaxVoxelBatch) return "`batch` must be at most " + std::to_string(kMaxVoxelBatch) + " voxels";
    // Written as !(x >= 0) and the like throughout, so that NaN is refused too.
    if (!(gradientSeedShare >= 0.0) || !(uniformSeedShare >= 0.0) || !(gradientSeedShare + uniformSeedShare > 0.0) ||
        !std::isfinite(gradientSeedShare + uniformSeedShare)) {
        return "`gradient_share` and `uniform_share` must be >= 0 and not both 0";
    }
    if (refreshEvery == 0) return "`refresh_every` must be positive";
    if (rebinEvery == 0) return "`rebin_every` must be positive";
    if (rowStride < 1 || rowStride > 64) return "`row_stride` must lie in [1, 64]";
    if (!(importance.uniformShare >= 0.0 && importance.uniformShare <= 1.0)) return "`mc_lambda` must lie in [0, 1]";
    if (!(importance.epsilon > 0.0) || !std::isfinite(importance.epsilon))
        return "`mc_epsilon` must be a positive number";
    if (slicePixels == 0 && schedule != SliceSchedule::None) return "`slice_pixels` must be positive";
    if (!(sliceMax >= 0.0 && sliceMax <= 1.0)) return "`slice_max` must lie in [0, 1]";
    if (!std::isfinite(sliceGamma)) return "`slice_gamma` must be a finite fraction of the budget";
    if (!(sliceBeta > 0.0) || !std::isfinite(sliceBeta)) return "`slice_beta` must be a positive number";
    if (!(learningRate > 0.0) || !std::isfinite(learningRate)) return "`lr` must be positive";
    if (!(finalRateFactor > 0.0) || finalRateFactor > 1.0) return "`lr_final` must lie in (0, 1]";
    if (!(cutoffSigmas >= 1.0f) || cutoffSigmas > 10.0f) return "`cutoff` must lie in [1, 10] sigmas";
    if (!(pruneAmplitude >= 0.0) || !std::isfinite(pruneAmplitude)) return "`prune_amplitude` must be a number >= 0";
    if (!(amplitudeSolveShare >= 0.0 && amplitudeSolveShare < 1.0)) return "`solve_share` must lie in [0, 1)";
    if (!(minSamplesPerGaussian >= 0.0) || !std::isfinite(minSamplesPerGaussian)) {
        return "`min_samples` must be a number >= 0";
    }
    if (heldOutVoxels == 0 || logEvery == 0) return "`held_out` and `log_every` must be positive";
    return "";
}

std::size_t FitSettings::batchFor(std::size_t count) const {
    if (voxelBatch > 0) return voxelBatch;
    const double sized = std::min(kBatchPerGaussian * double(count), double(kMaxVoxelBatch));
    return std::max(kLeastVoxelBatch, std::size_t(sized));
}

void applyAblation(Ablation ablation, FitSettings& settings) {
    switch (ablation) {
        case Ablation::Full:
            settings.importanceSampling = true;
            settings.schedule = SliceSchedule::VoxelsThenSlices;
            break;
        case Ablation::A1:
            settings.importanceSampling = false;
            settings.schedule = SliceSchedule::None;
            break;
        case Ablation::A2:
            settings.importanceSampling = false;
            settings.schedule = SliceSchedule::VoxelsThenSlices;
            break;
        case Ablation::A3:
            settings.importanceSampling = true;
            settings.schedule = SliceSchedule::SlicesThenVoxels;
            break;
        case Ablation::A4:
            settings.schedule = SliceSchedule::SlicesOnly;
            break;
        case Ablation::A5:
            settings.importanceSampling = true;
            settings.schedule = SliceSchedule::None;
            break;
    }
}

std::string ablationName(Ablation ablation) {
    static const char* names[] = {"full", "A1", "A2", "A3", "A4", "A5"};
    return names[int(ablation)];
}

Ablation ablationFromName(const std::string& name) {
    for (Ablation a : {Ablation::Full, Ablation::A1, Ablation::A2, Ablation::A3, Ablation::A4, Ablation::A5}) {
        if (ablationName(a) == name) return a;
    }
    throw InputError("`ablation`", "unknown value '" + name + "' (expected full, A1, A2, A3, A4 or A5)");
}

double sliceWeight(const FitSettings& settings, double t) {
    const auto logistic = [](double x) { return 1.0 / (1.0 + std::exp(-x)); };
    switch (settings.schedule) {
        case SliceSchedule::None:
            return 0.0;
        case SliceSchedule::VoxelsThenSlices:
            return settings.sliceMax * logistic((t - settings.sliceGamma) / settings.sliceBeta);
        case SliceSchedule::SlicesThenVoxels:
            return logistic(-(t - settings.sliceGamma) / settings.sliceBeta);
        case SliceSchedule::SlicesOnly:
            return 1.0;
    }
    return 0.0;
}

bool slicePassRuns(const FitSettings& settings, double t) {
    const double peak = settings.schedule == SliceSchedule::VoxelsThenSlices ? settings.sliceMax : 1.0;
    const double weight = sliceWeight(settings, t);
    return weight > 0.0 && weight >= kSliceSkipShare * peak;
}

}  // namespace gvr
