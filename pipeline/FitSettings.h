/// @file FitSettings.h
/// @brief Every constant of a fit, with its default, in one place.
#pragma once

#include "pipeline/BlockSampler.h"
#include "pipeline/GaussianKernel.h"
#include "pipeline/Initialisation.h"

#include <array>
#include <functional>
#include <string>

namespace gvr {

/// How the slice term's weight lambda_s(t) moves over the budget; t in [0, 1] is
/// the fraction of the iteration or time budget spent.
enum class SliceSchedule {
    None,              ///< lambda_s = 0: voxels only
    VoxelsThenSlices,  ///< lambda_s = max * sigmoid((t - gamma) / beta)
    SlicesThenVoxels,  ///< lambda_s = sigmoid(-(t - gamma) / beta): slices first, max ignored
    SlicesOnly,        ///< lambda_s = 1
};

/// The paper's full method and its ablations A1-A5.
enum class Ablation { Full, A1, A2, A3, A4, A5 };

/// The largest budgets a fit takes: beyond them a typo, not a plan (and 2^64 - 1
/// iterations would never end).
constexpr double kMaxFitSeconds = 1e6;
constexpr std::size_t kMaxFitIterations = 1'000'000'000;
constexpr std::size_t kMaxVoxelBatch = std::size_t(1) << 30;

struct FitSettings {
    std::size_t gaussians = 0;  ///< m; the caller derives it from --ratio
    /// 0 (the default): the fit keeps m, so that the file has the ratio asked for.
    /// Above 0, with a time budget, m is only a ceiling, a trade the user chooses:
    /// the fit times a few iterations at a probe count of at most 16,384, then
    /// starts again with as many Gaussians (up to m) as the time can give about this
    /// many voxel samples each, and checks that once more.
    double minSamplesPerGaussian = 0.0;
    std::size_t iterations = 0;  ///< stop after this many (0: no limit)
    double seconds = 0.0;        ///< stop after this long (0: no limit); one of the two must be set
    std::uint64_t seed = 1;

    double gradientSeedShare = 0.6;
    double uniformSeedShare = 0.4;

    /// Voxel samples per iteration (expected): whole 8^3 blocks drawn by error, every
    /// rowStride-th row of each (BlockSampler.h). 0: batchFor() sizes it to the count.
    std::size_t voxelBatch = 0;
    int rowStride = 4;
    std::size_t refreshEvery = 5;    ///< K: draw new blocks every K iterations
    std::size_t rebinEvery = 50;     ///< iterations between binning every Gaussian afresh
    bool importanceSampling = true;  ///< false: uniform voxels (lambda = 1)
    ImportanceSettings importance;

    std::size_t slicePixels = 8192;  ///< pixels per random plane
    SliceSchedule schedule = SliceSchedule::VoxelsThenSlices;
    double sliceMax = 0.1;    ///< lambda_s,max
    double sliceGamma = 0.5;  ///< gamma_s, as a fraction of the budget
    double sliceBeta = 0.08;  ///< beta_s, as a fraction of the budget

    /// Base learning rate (the paper's 5e-4), scaled per group: means move in
    /// voxels, so their rate is also multiplied by the longest side of the volume.
    double learningRate = 5e-4;
    /// Rotations and log-scales move 5 times as fast as with the per-sample engine,
    /// whose noisier gradients needed the smaller steps (README, "The block engine").
    std::array<double, kGroupCount> rateScale{1.0, 10.0, 50.0, 100.0, 10.0};
    /// The side, in voxels, that multiplies the means' rate; 0: the root mean square
    /// side of the fitted box. A brick takes its whole volume's, so that its means
    /// move as they would in a fit of the whole volume.
    double meanRateSide = 0.0;
    double finalRateFactor = 0.1;  ///< rates decay exponentially to this factor at the end

    float cutoffSigmas = kDefaultCutoffSigmas;
    std::size_t pruneEvery = 200;  ///< iterations between prune-and-respawn passes (0: never)
    double pruneAmplitude = 2e-3;  ///< Gaussians with |opacity * colour| below this are pruned

    /// After Adam: conjugate-gradient iterations of the dense least-squares amplitude
    /// solve (AmplitudeSolver.h; 0: none), and the share of a time budget kept for it.
    std::size_t amplitudeSolveIterations = 10;
    double amplitudeSolveShare = 0.1;
    /// The caller measures the fitted field densely (measureVolumeError) right after:
    /// a time budget then ends that much earlier, so that it covers the measurement.
    bool reserveMeasurement = false;
    /// The parameters as storage will give them back (quantised, perhaps fewer), if
    /// known: the amplitude solve then runs on the stored geometry and makes up for
    /// its rounding and for any Gaussians left out.
    std::function<GaussianParameters(const GaussianParameters&)> storedGeometry;
    /// How many more Gaussians the file has room for, given these, if the caller
    /// knows its byte budget: the fit then adds them where the error is largest, a few
    /// times before its last fifth. The count chosen before the fit assumes trained
    /// Gaussians, and seeds that have barely moved code smaller, which left files
    /// above the ratio asked (docs/benchmarks.md, "The file holds the ratio").
    std::function<std::size_t(const GaussianParameters&)> roomInBudget;
    /// Sees each iteration's gradient before the step, a range of Gaussians at a time
    /// (Gaussian first + i at index i); tests use it to inject the non-finite values
    /// that the fit must skip and survive.
    std::function<void(std::size_t iteration, std::size_t first, GaussianParameters& gradient)> gradientHook;

    std::size_t heldOutVoxels = 32768;  ///< fixed voxels for the PSNR curve
    std::size_t logEvery = 50;          ///< iterations between held-out PSNR evaluations

    /// Empty when the settings are usable, else what is wrong, naming the flag.
    std::string validate() const;

    /// The voxel batch for a fit of @a count Gaussians: voxelBatch if set, else
    /// kBatchPerGaussian samples a Gaussian and at least kLeastVoxelBatch.
    std::size_t batchFor(std::size_t count) const;
};

/// The default batch grows with the count: each step's pass over every Gaussian
/// (Adam, re-activation) then serves as many samples a Gaussian at any scale, and
/// nearly every Gaussian gets a gradient each step. A fixed 524,288 left most of a
/// large MRI's Gaussians without a gradient in a step (docs/benchmarks.md, "The
/// batch grows with the count").
constexpr std::size_t kLeastVoxelBatch = 524288;
constexpr double kBatchPerGaussian = 8.0;

/// Settings for the full method or one of the paper's ablations:
///   full  Monte Carlo importance voxels, then the slice curriculum
///   A1    uniform random voxels only
///   A2    uniform random voxels, then slices
///   A3    slices first, then importance voxels
///   A4    slices only
///   A5    Monte Carlo importance voxels only
void applyAblation(Ablation ablation, FitSettings& settings);

/// "full", "A1", ... "A5".
std::string ablationName(Ablation ablation);
/// @throw InputError for an unknown name.
Ablation ablationFromName(const std::string& name);

/// lambda_s(t) for the schedule; the voxel term gets 1 - lambda_s.
double sliceWeight(const FitSettings& settings, double t);

/// The slice pass is skipped while lambda_s(t) is below this share of its maximum:
/// it would cost as much as at full weight and move nothing.
constexpr double kSliceSkipShare = 0.01;
/// Whether the slice pass runs at @a t.
bool slicePassRuns(const FitSettings& settings, double t);

}  // namespace gvr
