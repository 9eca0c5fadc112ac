#include "Fitter.h"

#include "Adam.h"
#include "Error.h"
#include "Loss.h"
#include "Pruning.h"
#include "SliceSampler.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

/// A seed for one purpose at one iteration, so that runs are reproducible.
std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t purpose, std::uint64_t iteration) {
    std::seed_seq sequence{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(purpose),
                           std::uint32_t(iteration), std::uint32_t(iteration >> 32)};
    std::uint32_t words[2];
    sequence.generate(words, words + 2);
    return (std::uint64_t(words[0]) << 32) | words[1];
}

enum Purpose : std::uint64_t { kVoxels = 1, kSlices = 2, kHeldOut = 3, kSeeds = 4 };

void fillVoxelTargets(const VolumeTarget& target, SampleSet& set) {
    const int channels = target.channels();
    set.targets.resize(set.size() * channels);
    tbb::parallel_for(std::size_t(0), set.size(), [&](std::size_t s) {
        const auto& p = set.points[s];
        target.valueAt(openvdb::Coord(int(p[0]), int(p[1]), int(p[2])), &set.targets[s * channels]);
    });
}

SampleSet voxelSampleSet(const VolumeTarget& target, const std::vector<VoxelSample>& samples) {
    SampleSet set;
    set.points.resize(samples.size());
    set.weights.resize(samples.size());
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const openvdb::Coord& ijk = samples[s].ijk;
        set.points[s] = {float(ijk.x()), float(ijk.y()), float(ijk.z())};
        set.weights[s] = samples[s].weight / float(samples.size());
    }
    fillVoxelTargets(target, set);
    return set;
}

SampleSet sliceSampleSet(const VolumeTarget& target, std::size_t pixels, std::uint64_t seed) {
    SampleSet set;
    set.points = drawSlicePoints(target.box(), pixels, seed);
    set.weights.assign(set.size(), 1.0f / float(set.size()));
    set.targets.resize(set.size() * target.channels());
    tbb::parallel_for(std::size_t(0), set.size(), [&](std::size_t s) {
        target.trilinearAt(set.points[s].data(), &set.targets[s * target.channels()]);
    });
    return set;
}

/// Fixed voxels for the PSNR curve, drawn uniformly: at most a tenth of the box, so
/// that training keeps nearly every voxel (none at all from fewer than ten voxels).
std::vector<VoxelSample> heldOutVoxels(const VolumeTarget& target, std::size_t count, std::uint64_t seed) {
    ImportanceSettings uniform;
    uniform.uniformShare = 1.0;
    count = std::min<std::size_t>(count, std::size_t(target.box().volume() / 10));
    if (count == 0) return {};
    return ImportanceSampler(target.box(), uniform).draw(count, seed);
}

/// Where the residual of the last voxel batch is largest, one site per voxel.
std::vector<RespawnSite> respawnSites(const SampleSet& set, const std::vector<float>& squared,
                                      const GaussianField& field, std::size_t wanted) {
    std::vector<std::size_t> order(set.size());
    for (std::size_t s = 0; s < order.size(); ++s) order[s] = s;
    wanted = std::min(wanted, order.size());
    std::partial_sort(order.begin(), order.begin() + wanted, order.end(),
                      [&](std::size_t a, std::size_t b) { return squared[a] > squared[b] || (squared[a] == squared[b] && a < b); });
    std::vector<RespawnSite> sites;
    std::vector<std::uint32_t> hits;
    const int channels = field.channels();
    for (std::size_t k = 0; k < wanted; ++k) {
        const std::size_t s = order[k];
        RespawnSite site{set.points[s], {0, 0, 0}};
        float value[3];
        field.evaluate(site.position.data(), value, hits);
        for (int c = 0; c < channels; ++c) site.residual[c] = set.targets[s * channels + c] - value[c];
        if (sites.empty() || sites.back().position != site.position) sites.push_back(site);
    }
    return sites;
}

/// Keeps every parameter inside the ranges where the kernel is well defined.
void repair(GaussianParameters& params, const openvdb::CoordBBox& box) {
    const openvdb::Vec3f lower = box.min().asVec3s() - openvdb::Vec3f(8.0f);
    const openvdb::Vec3f upper = box.max().asVec3s() + openvdb::Vec3f(8.0f);
    tbb::parallel_for(std::size_t(0), params.count(), [&](std::size_t i) {
        float* mean = params.at(kMeans, i);
        for (int a = 0; a < 3; ++a) mean[a] = std::clamp(mean[a], lower[a], upper[a]);
        float* logScale = params.at(kLogScales, i);
        for (int a = 0; a < 3; ++a) logScale[a] = std::clamp(logScale[a], kMinLogScale, kMaxLogScale);
        float* logit = params.at(kOpacityLogits, i);
        *logit = std::clamp(*logit, -12.0f, 12.0f);
        // Values are normalised to [0, 1]; a colour far outside is a runaway, not a fit.
        float* colour = params.at(kColours, i);
        for (int c = 0; c < params.channels; ++c) colour[c] = std::clamp(colour[c], -16.0f, 16.0f);
        float* q = params.at(kRotations, i);
        const float norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (norm > 1e-6f) {
            for (int k = 0; k < 4; ++k) q[k] /= norm;
        } else {
            q[0] = 1.0f;
            q[1] = q[2] = q[3] = 0.0f;
        }
    });
}

class FitLoop {
public:
    FitLoop(const VolumeTarget& target, const FitSettings& settings)
        : mTarget(target), mSettings(settings), mStart(Clock::now()),
          mSampler(target.box(), samplerSettings(settings)) {}

    GaussianParameters run(const FitObserver& observer, FitReport& report);

private:
    static ImportanceSettings samplerSettings(const FitSettings& settings) {
        ImportanceSettings importance = settings.importance;
        if (!settings.importanceSampling) importance.uniformShare = 1.0;
        return importance;
    }

    double elapsed() const { return std::chrono::duration<double>(Clock::now() - mStart).count(); }

    /// The part of a time budget for Adam; the amplitude solve gets the rest.
    double adamSeconds() const {
        const bool solve = mSettings.amplitudeSolveIterations > 0;
        return mSettings.seconds * (solve ? 1.0 - mSettings.amplitudeSolveShare : 1.0);
    }

    void solveAmplitudesAtTheEnd(const std::vector<openvdb::Coord>& heldOutCoords, const SampleSet& heldOut,
                                 std::size_t iteration, const FitObserver& observer);

    double fractionDone(std::size_t iteration) const {
        double fraction = 0.0;
        if (mSettings.iterations > 0) fraction = double(iteration) / double(mSettings.iterations);
        if (mSettings.seconds > 0.0) fraction = std::max(fraction, elapsed() / adamSeconds());
        return std::min(fraction, 1.0);
    }

    std::array<double, kGroupCount> rates(double fraction) const {
        const double longestSide = mSettings.meanRateSide > 0.0
                                       ? mSettings.meanRateSide
                                       : double(mTarget.box().dim().asVec3d().length() / std::sqrt(3.0));
        const double decay = std::pow(mSettings.finalRateFactor, fraction);
        std::array<double, kGroupCount> rates;
        for (int g = 0; g < kGroupCount; ++g) {
            rates[g] = mSettings.learningRate * mSettings.rateScale[g] * decay;
        }
        rates[kMeans] *= longestSide;
        return rates;
    }

    void initialise(std::size_t count);
    std::size_t trainableCount() const;
    void fitCountToTheTime();
    double step(std::size_t iteration, double fraction, FitProgress& progress);
    bool refreshField();

    const VolumeTarget& mTarget;
    const FitSettings& mSettings;
    Clock::time_point mStart;
    ImportanceSampler mSampler;
    GaussianParameters mParams, mGradient, mBackup;
    GaussianField mField;
    GradientChunks mChunks;
    std::vector<VoxelSample> mLastDraw;
    SampleSet mVoxels;
    std::vector<float> mVoxelResiduals;
    std::unique_ptr<Adam> mAdam;
    FitReport mReport;

    /// Seconds per iteration measured at a Gaussian count, to size the count to the time.
    struct Pace {
        std::size_t count;
        double secondsPerIteration;
    };
    static constexpr std::size_t kPaceIterations = 5;
    static constexpr std::size_t kProbeGaussians = 16384;
    std::vector<Pace> mPaces;
    bool mPacing = false;
    double mPaceStart = 0.0;
    std::size_t mPaceIterations = 0;
};

void FitLoop::initialise(std::size_t count) {
    SeedSettings seeds;
    seeds.count = count;
    seeds.gradientShare = mSettings.gradientSeedShare;
    seeds.uniformShare = mSettings.uniformSeedShare;
    seeds.seed = streamSeed(mSettings.seed, kSeeds, 0);
    mParams = initialiseGaussians(mTarget, seeds);
    mReport.requestedGaussians = count < mSettings.gaussians ? mSettings.gaussians : 0;
    mAdam = std::make_unique<Adam>(mParams.count(), mParams.channels);
    mVoxels = SampleSet();
    mVoxelResiduals.clear();
    mLastDraw.clear();
    mPaceStart = elapsed();
    mPaceIterations = 0;
}

/// The count that the rest of the time can train with minSamplesPerGaussian voxel
/// samples each, if an iteration over m Gaussians takes a + b m seconds: from one
/// pace, a constant (off in the direction of the count it was timed at, since fewer
/// Gaussians are faster); from two, the line through both.
std::size_t FitLoop::trainableCount() const {
    const double samples = std::max(adamSeconds() - elapsed(), 0.0) * double(mSettings.voxelBatch) /
                           mSettings.minSamplesPerGaussian;  // R: m (a + b m) = R
    double a = mPaces.back().secondsPerIteration, b = 0.0;
    if (mPaces.size() >= 2) {
        const Pace& first = mPaces[0];
        const Pace& last = mPaces.back();
        b = std::max((first.secondsPerIteration - last.secondsPerIteration) / (double(first.count) - double(last.count)), 0.0);
        a = std::max(last.secondsPerIteration - b * double(last.count), 1e-6);
    }
    const double count = b > 0.0 ? (-a + std::sqrt(a * a + 4.0 * b * samples)) / (2.0 * b) : samples / a;
    return std::size_t(std::clamp(count, 1.0, double(mSettings.gaussians)));
}

/// After kPaceIterations timed iterations: if the time can train clearly more or
/// fewer Gaussians than this, start again with as many as it can. A second pace
/// corrects the first estimate, which assumed the time per iteration does not
/// depend on the count; there is no third.
void FitLoop::fitCountToTheTime() {
    mPaces.push_back({mParams.count(), (elapsed() - mPaceStart) / double(kPaceIterations)});
    if (elapsed() > 0.5 * adamSeconds()) {  // too late to start again: keep what has been trained
        mPacing = false;
        return;
    }
    const std::size_t trainable = trainableCount();
    const double change = double(trainable) / double(mParams.count());
    // Small changes are not worth a restart, except to reach the byte budget's count.
    const bool reachesTheAllowance = trainable == mSettings.gaussians && trainable != mParams.count();
    const bool restart = reachesTheAllowance || change > 1.25 || change < 0.8;
    mPacing = restart && mPaces.size() < 2;
    if (restart) initialise(trainable);
}

/// Brings the field up to date with the parameters; rebuilds the BVH only when
/// a Gaussian has left its slack box. @return true when the BVH was rebuilt.
bool FitLoop::refreshField() {
    if (mField.update(mParams)) return false;
    // Slack lets most steps skip the rebuild; queries stay exact either way.
    mField.rebuild(mParams, mSettings.cutoffSigmas, /*fastBuild=*/true, 0.75f, 0.1f);
    return true;
}

double FitLoop::step(std::size_t iteration, double fraction, FitProgress& progress) {
    const double sliceShare = sliceWeight(mSettings, fraction);
    const double voxelShare = 1.0 - sliceShare;
    const bool rebuilt = refreshField();
    mChunks.reset(mParams.count());

    double loss = 0.0;
    if (voxelShare > 0.0) {
        const bool redraw = iteration % mSettings.refreshEvery == 0 || mVoxels.size() == 0;
        if (redraw) {
            if (!mVoxelResiduals.empty()) mSampler.recordErrors(mLastDraw, mVoxelResiduals);
            mLastDraw = mSampler.draw(mSettings.voxelBatch, streamSeed(mSettings.seed, kVoxels, iteration));
            mVoxels = voxelSampleSet(mTarget, mLastDraw);
        }
        if (redraw || rebuilt) findCandidates(mField, mVoxels);
        loss += weightedSquaredError(mField, mVoxels, voxelShare, &mChunks, &mVoxelResiduals);
    }
    if (sliceShare > 0.0) {
        const SampleSet slice = sliceSampleSet(mTarget, mSettings.slicePixels,
                                               streamSeed(mSettings.seed, kSlices, iteration));
        loss += weightedSquaredError(mField, slice, sliceShare, &mChunks);
    }
    mChunks.sumInto(mField, mGradient);
    if (mSettings.gradientHook) mSettings.gradientHook(iteration, mGradient);
    progress.sliceWeight = sliceShare;

    if (!std::isfinite(loss) || !mGradient.allFinite()) {
        ++mReport.skippedSteps;
        mVoxelResiduals.clear();  // NaN residuals would poison the sampler's errors and the respawn order
        return loss;
    }
    mBackup = mParams;
    mAdam->step(mParams, mGradient, rates(fraction));
    repair(mParams, mTarget.box());
    if (!mParams.allFinite()) {
        mParams = mBackup;
        ++mReport.skippedSteps;
    }
    return loss;
}

void FitLoop::solveAmplitudesAtTheEnd(const std::vector<openvdb::Coord>& heldOutCoords, const SampleSet& heldOut,
                                      std::size_t iteration, const FitObserver& observer) {
    AmplitudeSolveSettings solve;
    solve.excluded = heldOutCoords;
    solve.iterations = mSettings.amplitudeSolveIterations;
    solve.cutoffSigmas = mSettings.cutoffSigmas;
    if (mSettings.seconds > 0.0) solve.seconds = std::max(mSettings.seconds - elapsed(), 1e-9);
    if (mSettings.storedGeometry) mParams = mSettings.storedGeometry(mParams);
    mReport.amplitudeSolve = solveAmplitudes(mParams, mTarget, solve);
    if (!observer || mParams.count() == 0) return;
    refreshField();
    FitProgress progress;
    progress.iteration = iteration;
    progress.seconds = elapsed();
    progress.fraction = 1.0;
    progress.gaussians = mParams.count();
    progress.skippedSteps = mReport.skippedSteps;
    progress.heldOutEvaluated = true;
    progress.heldOutPsnr = psnrFromMse(weightedSquaredError(mField, heldOut, 1.0) / mTarget.channels(), mTarget.peak());
    observer(progress);
}

GaussianParameters FitLoop::run(const FitObserver& observer, FitReport& report) {
    const std::vector<VoxelSample> heldOutDraw =
        heldOutVoxels(mTarget, mSettings.heldOutVoxels, streamSeed(mSettings.seed, kHeldOut, 0));
    std::vector<openvdb::Coord> heldOutCoords;
    for (const VoxelSample& sample : heldOutDraw) heldOutCoords.push_back(sample.ijk);
    mSampler.exclude(heldOutCoords);  // an honest PSNR curve: training never sees them
    const SampleSet heldOut = voxelSampleSet(mTarget, heldOutDraw);
    mPacing = mSettings.seconds > 0.0 && mSettings.minSamplesPerGaussian > 0.0 && mSettings.voxelBatch > 0;
    // Timing a probe rather than the whole allowance keeps the peak memory near
    // what the time can train, not what the byte budget allows.
    initialise(mPacing ? std::min(mSettings.gaussians, kProbeGaussians) : mSettings.gaussians);

    std::size_t iteration = 0;
    while (mParams.count() > 0) {
        const double fraction = fractionDone(iteration);
        if (fraction >= 1.0) break;
        FitProgress progress;
        progress.loss = step(iteration, fraction, progress);
        ++iteration;
        if (mPacing && ++mPaceIterations == kPaceIterations) fitCountToTheTime();

        if (mSettings.pruneEvery > 0 && iteration % mSettings.pruneEvery == 0 && !mVoxelResiduals.empty()) {
            const std::size_t budget = mParams.count();
            const std::vector<RespawnSite> sites =
                respawnSites(mVoxels, mVoxelResiduals, mField, budget / 20 + 1);
            const PruneResult pruned = pruneAndRespawn(mParams, *mAdam, mSettings.pruneAmplitude, sites);
            mReport.pruned += pruned.removed;
            mReport.respawned += pruned.respawned;
        }
        progress.iteration = iteration;
        progress.seconds = elapsed();
        progress.fraction = fractionDone(iteration);
        progress.gaussians = mParams.count();
        progress.skippedSteps = mReport.skippedSteps;
        if (iteration % mSettings.logEvery == 0 || progress.fraction >= 1.0) {
            refreshField();
            progress.heldOutEvaluated = true;
            // The loss sums channels; PSNR uses the mean over channels.
            const double mse = weightedSquaredError(mField, heldOut, 1.0) / mTarget.channels();
            progress.heldOutPsnr = psnrFromMse(mse, mTarget.peak());
        }
        if (observer) observer(progress);
    }
    mReport.iterations = iteration;
    if (mSettings.amplitudeSolveIterations > 0) solveAmplitudesAtTheEnd(heldOutCoords, heldOut, iteration, observer);
    mReport.seconds = elapsed();
    report = mReport;
    return std::move(mParams);
}

}  // namespace

double psnrFromMse(double mse, double peak) {
    if (mse <= 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak / mse);
}

GaussianParameters fitGaussians(const VolumeTarget& target, const FitSettings& settings,
                                const FitObserver& observer, FitReport* report) {
    const std::string problem = settings.validate();
    if (!problem.empty()) throw InputError("fit settings", problem);
    FitReport ignored;
    FitLoop loop(target, settings);
    return loop.run(observer, report ? *report : ignored);
}

}  // namespace gvr
