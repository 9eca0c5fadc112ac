#include "pipeline/Fitter.h"

#include "pipeline/Adam.h"
#include "pipeline/BlockLoss.h"
#include "pipeline/Error.h"
#include "pipeline/FieldAccuracy.h"
#include "pipeline/Loss.h"
#include "pipeline/MortonCode.h"
#include "pipeline/ProcessMemory.h"
#include "pipeline/Pruning.h"
#include "pipeline/SliceSampler.h"
#include "pipeline/StreamSeed.h"
#include "pipeline/UniformVoxels.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

enum Purpose : std::uint64_t { kVoxels = 1, kSlices = 2, kHeldOut = 3, kSeeds = 4, kFills = 5, kRespawns = 6 };

void fillVoxelTargets(const VolumeTarget& target, SampleSet& set) {
    const int channels = target.channels();
    set.targets.resize(set.size() * channels);
    tbb::parallel_for(std::size_t(0), set.size(), [&](std::size_t s) {
        const auto& p = set.points[s];
        target.valueAt(openvdb::Coord(int(p[0]), int(p[1]), int(p[2])), &set.targets[s * channels]);
    });
}

/// Voxels weighted equally, for a plain mean of their squared residuals.
SampleSet voxelSampleSet(const VolumeTarget& target, const std::vector<openvdb::Coord>& voxels) {
    SampleSet set;
    set.points.resize(voxels.size());
    set.weights.assign(voxels.size(), 1.0f / float(voxels.size()));
    for (std::size_t s = 0; s < voxels.size(); ++s)
        set.points[s] = {float(voxels[s].x()), float(voxels[s].y()), float(voxels[s].z())};
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
std::vector<openvdb::Coord> heldOutVoxels(const VolumeTarget& target, std::size_t count, std::uint64_t seed) {
    count = std::min<std::size_t>(count, std::size_t(target.box().volume() / 10));
    return drawUniformVoxels(target.box(), count, seed);
}

/// The Gaussians in Morton order of their means (to the voxel), ties in index order:
/// a block's Gaussians then lie near each other in memory.
std::vector<std::uint32_t> spatialOrder(const GaussianParameters& params, const openvdb::CoordBBox& box) {
    const std::size_t count = params.count();
    std::vector<std::uint64_t> codes(count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
        std::uint32_t cell[3];
        for (int a = 0; a < 3; ++a) {
            // Means lie within 8 voxels of the box (repair), so this is never negative.
            const double offset = double(params.at(kMeans, i)[a]) - box.min()[a] + 8.0;
            cell[a] = std::uint32_t(std::clamp(offset, 0.0, double((1u << 21) - 1)));
        }
        codes[i] = mortonCode(cell[0], cell[1], cell[2]);
    });
    std::vector<std::uint32_t> order(count);
    for (std::uint32_t i = 0; i < count; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return codes[a] < codes[b] || (codes[a] == codes[b] && a < b); });
    return order;
}

/// Each block's mean squared residual over the voxels it evaluated (NaN for none).
std::vector<double> meanSquaredPerBlock(const std::vector<BlockOutcome>& outcomes) {
    std::vector<double> means(outcomes.size());
    for (std::size_t k = 0; k < outcomes.size(); ++k) {
        means[k] = outcomes[k].voxels ? outcomes[k].squared / outcomes[k].voxels : std::nan("");
    }
    return means;
}

/// Keeps Gaussian @a i's parameters inside the ranges where the kernel is well
/// defined: means within [lower, upper], the rest as GaussianKernel.h allows.
void repair(GaussianParameters& params, std::size_t i, const openvdb::Vec3f& lower, const openvdb::Vec3f& upper) {
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
}

class FitLoop {
public:
    FitLoop(const VolumeTarget& target, const FitSettings& settings)
        : mTarget(target),
          mSettings(settings),
          mStart(Clock::now()),
          mHeldOut(heldOutVoxels(target, settings.heldOutVoxels, streamSeed(settings.seed, kHeldOut, 0))),
          mGrid(target.box(), mHeldOut),  // an honest PSNR curve: training never sees them
          mSampler(mGrid, samplerSettings(settings), settings.rowStride),
          mBins(mGrid, kBinSlackVoxels, kBinSlackFraction) {}

    GaussianParameters run(const FitObserver& observer, FitReport& report);

private:
    static ImportanceSettings samplerSettings(const FitSettings& settings) {
        ImportanceSettings importance = settings.importance;
        if (!settings.importanceSampling) importance.uniformShare = 1.0;
        return importance;
    }

    double elapsed() const { return std::chrono::duration<double>(Clock::now() - mStart).count(); }

    /// The part of a time budget for Adam: the amplitude solve gets what it needs up
    /// to its share, and what follows the fit its estimated time.
    double adamSeconds() const { return std::max(mSettings.seconds - solveSeconds() - closingSeconds(), 0.0); }

    /// Time kept for the amplitude solve: its share of the budget, or less when its
    /// passes need less, and the coding of the stored geometry before it. Each CG
    /// iteration, and the passes before and after them, costs about a dense
    /// measurement, so a long budget no longer leaves most of its share unused.
    double solveSeconds() const {
        if (!solving()) return 0.0;
        const double passes = double(mSettings.amplitudeSolveIterations + 2);
        const double coding = mSettings.storedGeometry ? codingSeconds() : 0.0;
        return coding + std::min(mSettings.amplitudeSolveShare * mSettings.seconds,
                                 passes * kMeasurementMargin * mMeasurementSeconds);
    }

    /// Time kept after the solve: the caller's dense measurement (reserveMeasurement)
    /// and the coding of the file within its byte budget.
    double closingSeconds() const {
        const double measure = mSettings.reserveMeasurement ? kMeasurementMargin * mMeasurementSeconds : 0.0;
        return measure + codingSeconds();
    }

    /// The time to code the file within its budget, from the last time the room in it
    /// was measured: a trained field codes over the room left, so about twice.
    double codingSeconds() const { return kCodingsWithinTheBudget * mRoomSeconds; }

    /// Whether the iteration just done is the last: the budget is spent, or the next
    /// iteration would end further past it than stopping now ends short of it (a
    /// large volume's iterations are long, and one came on top of its budget:
    /// docs/benchmarks.md, "The time budget").
    bool lastIteration(std::size_t iteration) const {
        if (fractionDone(iteration) >= 1.0) return true;
        return mSettings.seconds > 0.0 && elapsed() + 0.5 * mIterationSeconds >= adamSeconds();
    }

    /// Whether the amplitude solve runs: under a time budget, only if its share holds
    /// its first pass, one iteration and its closing pass, each about a measurement.
    bool solving() const {
        if (mSettings.amplitudeSolveIterations == 0) return false;
        if (mSettings.seconds <= 0.0) return true;
        // A share of nothing holds no pass, even before a pass has been timed.
        const double share = mSettings.amplitudeSolveShare * mSettings.seconds;
        return share > 0.0 && share >= 3.0 * mMeasurementSeconds;
    }

    /// Why the amplitude solve does not run, in words for the report; empty if it does.
    std::string whyNotSolving() const {
        if (solving()) return "";
        if (mSettings.amplitudeSolveIterations == 0) return "no solve iterations were asked for";
        std::ostringstream why;
        why << std::setprecision(2) << "its share of the time budget, "
            << mSettings.amplitudeSolveShare * mSettings.seconds << " s, holds fewer than the 3 dense passes it needs ("
            << mMeasurementSeconds << " s each)";
        return why.str();
    }

    /// whyNotSolving(), once Adam is over: a set-up that outlasted the budget (a loaded
    /// machine's, say) leaves no time for the solve's two passes either.
    std::string whyNotSolvingNow() const {
        const std::string why = whyNotSolving();
        if (!why.empty() || !(mSettings.seconds > 0.0)) return why;
        return elapsed() + closingSeconds() >= mSettings.seconds ? "the time budget was spent before it" : "";
    }

    /// Whether to re-time a dense pass over the field: at a few points of a time
    /// budget, as the Gaussians grow and the count settles.
    bool measurementDue(double fraction) const { return mSettings.seconds > 0.0 && fraction >= mNextEstimate; }

    /// Needs the field's BVH: called while it is built.
    void estimateMeasurement(double fraction) {
        mMeasurementSeconds = estimateMeasurementSeconds(mField, mTarget);
        mNextEstimate = fraction < 0.5 ? 0.5 : fraction < 0.8 ? 0.8 : fraction < 0.95 ? 0.95 : 2.0;
    }

    void solveAmplitudesAtTheEnd(const std::vector<openvdb::Coord>& heldOutCoords, const SampleSet& heldOut,
                                 std::size_t iteration, const FitObserver& observer);

    /// What the user sees: under a time budget, the share of the whole of it
    /// (Adam, the solve and the measurement kept for), so that the bar keeps moving
    /// through the solve; else the share of the iterations.
    double shownFraction(std::size_t iteration) const {
        if (mSettings.seconds > 0.0) return std::min(elapsed() / mSettings.seconds, 1.0);
        return fractionDone(iteration);
    }

    /// Where the fit stands, into @a progress: iterations, time, share, count.
    void recordStanding(std::size_t iteration, FitProgress& progress) const {
        progress.iteration = iteration;
        progress.seconds = elapsed();
        progress.fraction = shownFraction(iteration);
        progress.gaussians = mParams.count();
        progress.skippedSteps = mReport.skippedSteps;
    }

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
    void fillTheByteBudget(double fraction);
    std::vector<RespawnSite> largestResidualSites(std::size_t count, std::uint64_t seed) const;
    std::size_t trainableCount() const;
    void fitCountToTheTime();
    double step(std::size_t iteration, double fraction, FitProgress& progress);
    double voxelLoss(std::size_t iteration, double share);
    /// What one pass of updateEveryGaussian() saw.
    struct Update {
        std::size_t withGradient = 0;  ///< Gaussians that got a gradient
        std::size_t kept = 0;          ///< Gaussians kept for a non-finite gradient or result
    };
    Update updateEveryGaussian(std::size_t iteration);
    void refreshField(std::size_t iteration);
    double heldOutPsnr(const SampleSet& heldOut) const;
    void releaseTrainingState();

    const VolumeTarget& mTarget;
    const FitSettings& mSettings;
    Clock::time_point mStart;
    std::vector<openvdb::Coord> mHeldOut;
    BlockGrid mGrid;
    BlockSampler mSampler;
    BlockBins mBins;
    GaussianParameters mParams;
    GaussianField mField;
    GradientChunks mChunks;
    std::vector<SampledBlock> mBlocks;
    std::vector<BlockOutcome> mOutcomes;
    bool mRebin = true;         ///< the count or the numbering changed: bin afresh
    std::size_t mBinnedAt = 0;  ///< iteration of the last binning
    std::unique_ptr<Adam> mAdam;
    std::size_t mBatch = 0;  ///< voxel samples a step, for the count initialised
    FitReport mReport;

    /// Seconds per voxel sample measured at a Gaussian count (whose batch is its
    /// own), to size the count to the time.
    struct Pace {
        std::size_t count;
        double secondsPerSample;
    };
    FitObserver mObserver;  ///< run()'s, for the set-up's progress
    static constexpr std::size_t kPaceIterations = 5;
    /// The estimate of the measurement is from a sample of blocks, and the field
    /// still grows a little after the last one, at 95 % of Adam's time. Half as much
    /// again kept the chest's fit within its budget (docs/benchmarks.md, "The time
    /// budget").
    static constexpr double kMeasurementMargin = 1.2;
    double mMeasurementSeconds = 0.0;
    static constexpr double kCodingsWithinTheBudget = 2.0;
    double mRoomSeconds = 0.0;       ///< what roomInBudget took, the last time it was asked
    double mIterationSeconds = 0.0;  ///< the last iteration's, with its pruning, fill and log
    double mNextEstimate = 0.0;
    static constexpr std::size_t kProbeGaussians = 16384;
    /// Where in the fit the byte budget's room is measured and filled: early enough
    /// that the last Gaussians added get 40 % of the training, few enough that
    /// coding the file to measure it (at level 19) stays a small share.
    static constexpr std::array<double, 2> kFillPoints = {0.25, 0.6};
    static constexpr std::size_t kCandidatesPerSite = 4;
    std::size_t mFills = 0;  ///< of kFillPoints passed
    /// A restart at most multiplies the count by this. One pace cannot see how an
    /// iteration's cost grows with the count, so its estimate overshoots, and the
    /// overshoot set the peak memory: a large MRI seeded far more Gaussians than its
    /// second pace settled on.
    static constexpr double kMaxPaceGrowth = 8.0;
    static constexpr std::size_t kMaxPaces = 3;
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
    mParams = initialiseGaussians(mTarget, seeds, [this](double fraction) {
        if (!mObserver) return;
        FitProgress progress;
        recordStanding(0, progress);
        progress.setUp = fraction;
        mObserver(progress);
    });
    mReport.requestedGaussians = count < mSettings.gaussians ? mSettings.gaussians : 0;
    mAdam = std::make_unique<Adam>(mParams.count(), mParams.channels);
    mBatch = mSettings.batchFor(mParams.count());
    mBlocks.clear();
    mOutcomes.clear();
    mRebin = true;
    mPaceStart = elapsed();
    mPaceIterations = 0;
}

/// Adds the Gaussians the file has room for as each fill point is passed. Not
/// while the time paces the count: a count below the ratio's has room by choice.
void FitLoop::fillTheByteBudget(double fraction) {
    if (!mSettings.roomInBudget || mPacing || mReport.requestedGaussians > 0) return;
    if (mFills == kFillPoints.size() || fraction < kFillPoints[mFills]) return;
    while (mFills < kFillPoints.size() && fraction >= kFillPoints[mFills]) ++mFills;
    const double start = elapsed();
    const std::size_t room = mSettings.roomInBudget(mParams);
    mRoomSeconds = elapsed() - start;
    if (room == 0) return;
    const std::size_t added =
        addGaussiansAt(mParams, *mAdam, largestResidualSites(room, streamSeed(mSettings.seed, kFills, mFills)), room);
    mReport.added += added;
    mRebin = mRebin || added > 0;
    mBatch = mSettings.batchFor(mParams.count());
}

/// Up to @a count sites, for pruning and the fill: the voxels of largest residual
/// among kCandidatesPerSite times as many trainable ones drawn uniformly, less those
/// whose residual a new Gaussian could not hold without being pruned itself. The
/// blocks of a batch would give too few (ct-head at 10:1: 13,500, with room for 600k).
std::vector<RespawnSite> FitLoop::largestResidualSites(std::size_t count, std::uint64_t seed) const {
    std::vector<openvdb::Coord> voxels = drawUniformVoxels(mTarget.box(), kCandidatesPerSite * count, seed);
    // A Gaussian fitted to a held-out voxel's residual would flatter the curve.
    voxels.erase(
        std::remove_if(voxels.begin(), voxels.end(), [&](const openvdb::Coord& v) { return !mGrid.trainable(v); }),
        voxels.end());
    const SampleSet candidates = voxelSampleSet(mTarget, voxels);
    const std::vector<float> residual = residualsAt(mField, candidates, &mBins);
    const int channels = mTarget.channels();
    std::vector<float> largest(candidates.size(), 0.0f);
    std::vector<std::size_t> order;
    for (std::size_t s = 0; s < candidates.size(); ++s) {
        for (int c = 0; c < channels; ++c) largest[s] = std::max(largest[s], std::abs(residual[s * channels + c]));
        if (largest[s] >= mSettings.pruneAmplitude) order.push_back(s);
    }
    count = std::min(count, order.size());
    std::partial_sort(order.begin(), order.begin() + count, order.end(), [&](std::size_t a, std::size_t b) {
        return largest[a] > largest[b] || (largest[a] == largest[b] && a < b);
    });
    std::vector<RespawnSite> sites(count);
    for (std::size_t k = 0; k < count; ++k) {
        const std::size_t s = order[k];
        sites[k].position = candidates.points[s];
        std::fill(sites[k].residual.begin(), sites[k].residual.end(), 0.0f);
        std::copy_n(&residual[s * channels], channels, sites[k].residual.begin());
    }
    return sites;
}

/// The count that the rest of the time can train with minSamplesPerGaussian voxel
/// samples each, if a sample costs a + b m seconds at m Gaussians: from one pace, a
/// constant (off in the direction of the count it was timed at, since fewer
/// Gaussians are faster); from two, the line through both.
std::size_t FitLoop::trainableCount() const {
    const double seconds = std::max(adamSeconds() - elapsed(), 0.0) / mSettings.minSamplesPerGaussian;
    double a = mPaces.back().secondsPerSample, b = 0.0;  // m (a + b m) = seconds
    if (mPaces.size() >= 2) {
        const Pace& first = mPaces[0];
        const Pace& last = mPaces.back();
        b = std::max((first.secondsPerSample - last.secondsPerSample) / (double(first.count) - double(last.count)),
                     0.0);
        a = std::max(last.secondsPerSample - b * double(last.count), 1e-12);
    }
    const double count = b > 0.0 ? (-a + std::sqrt(a * a + 4.0 * b * seconds)) / (2.0 * b) : seconds / a;
    return std::size_t(std::clamp(count, 1.0, double(mSettings.gaussians)));
}

/// After kPaceIterations timed iterations: if the time can train clearly more or
/// fewer Gaussians than this, start again with as many as it can, at most
/// kMaxPaceGrowth times as many. Later paces correct the first estimate, which
/// assumed the time per iteration does not depend on the count.
void FitLoop::fitCountToTheTime() {
    const double samples = double(kPaceIterations) * double(mBatch);
    mPaces.push_back({mParams.count(), (elapsed() - mPaceStart) / samples});
    if (elapsed() > 0.5 * adamSeconds()) {  // too late to start again: keep what has been trained
        mPacing = false;
        return;
    }
    const std::size_t trainable = std::min(trainableCount(), std::size_t(kMaxPaceGrowth * double(mParams.count())));
    const double change = double(trainable) / double(mParams.count());
    // Small changes are not worth a restart, except to reach the byte budget's count.
    const bool reachesTheAllowance = trainable == mSettings.gaussians && trainable != mParams.count();
    const bool restart = reachesTheAllowance || change > 1.25 || change < 0.8;
    mPacing = restart && mPaces.size() < kMaxPaces;
    if (restart) initialise(trainable);
}

/// Brings the bins up to date with the field, which the update pass keeps current:
/// the few Gaussians that moved out of their blocks are binned again, and every
/// Gaussian is binned afresh (renumbered in space, the field re-activated, the BVH
/// rebuilt, one query per block) every rebinEvery iterations, when the count or
/// the numbering changed, or when the measurement is to be timed. The BVH is freed
/// once the bins are built: the fit asks only them, and the BVH was a large share
/// of its memory (docs/benchmarks.md, "A fit's memory").
void FitLoop::refreshField(std::size_t iteration) {
    const double fraction = fractionDone(iteration);
    const bool timeMeasurement = measurementDue(fraction);
    if (mRebin || timeMeasurement || iteration >= mBinnedAt + mSettings.rebinEvery) {
        // The last step's gradient sums are dead until the next step fills them again;
        // free them, or the BVH built below comes on top and sets the fit's peak memory.
        mChunks = GradientChunks();
        const std::vector<std::uint32_t> order = spatialOrder(mParams, mTarget.box());
        mParams.permute(order);
        if (mAdam) mAdam->permute(order);  // none once the training is over
        mField.rebuild(mParams, mSettings.cutoffSigmas, /*fastBuild=*/true, kBinSlackVoxels, kBinSlackFraction);
        mBins.build(mField);
        if (timeMeasurement) estimateMeasurement(fraction);
        mField.releaseBvh();
        mRebin = false;
        mBinnedAt = iteration;
        releaseFreedMemory();
        return;
    }
    mBins.follow(mField);
}

/// The voxel term over this iteration's blocks, its gradient into mChunks, and
/// what each block showed into the sampler's errors.
double FitLoop::voxelLoss(std::size_t iteration, double share) {
    if (iteration % mSettings.refreshEvery == 0 || mBlocks.empty()) {
        mBlocks = mSampler.draw(double(mBatch), streamSeed(mSettings.seed, kVoxels, iteration));
    }
    BlockLossSettings settings;
    settings.scale = share / double(std::max<std::uint64_t>(mGrid.trainableVoxels(), 1));
    settings.rowStride = mSampler.rowStride();
    const double loss = blockSquaredError(mField, mBins, mTarget, mBlocks, settings, &mChunks, &mOutcomes);
    for (const BlockOutcome& outcome : mOutcomes) mReport.voxelSamples += outcome.voxels;
    if (std::isfinite(loss)) mSampler.recordErrors(mBlocks, meanSquaredPerBlock(mOutcomes));
    return loss;
}

double FitLoop::step(std::size_t iteration, double fraction, FitProgress& progress) {
    const double sliceShare = sliceWeight(mSettings, fraction);
    const double voxelShare = 1.0 - sliceShare;
    refreshField(iteration);
    mChunks.reset(mParams.count());

    double loss = 0.0;
    if (voxelShare > 0.0) loss += voxelLoss(iteration, voxelShare);
    if (slicePassRuns(mSettings, fraction)) {
        const SampleSet slice =
            sliceSampleSet(mTarget, mSettings.slicePixels, streamSeed(mSettings.seed, kSlices, iteration));
        loss += weightedSquaredError(mField, slice, sliceShare, &mChunks, &mBins);
    }
    progress.sliceWeight = sliceShare;
    if (!std::isfinite(loss)) {
        ++mReport.skippedSteps;
        mOutcomes.clear();  // NaN residuals would poison the respawn order
        return loss;
    }
    mAdam->beginStep(rates(fraction));
    const Update update = updateEveryGaussian(iteration);
    if (update.kept > 0) ++mReport.skippedSteps;
    progress.gradientShare = mParams.count() ? double(update.withGradient) / double(mParams.count()) : 0.0;
    mReport.meanGradientShare += progress.gradientShare;
    return loss;
}

/// The gradient, Adam, repair and re-activation, a Gaussian at a time in one
/// parallel pass: each range's gradient is summed from the chunks just before its
/// step, so no gradient of every Gaussian is ever held.
FitLoop::Update FitLoop::updateEveryGaussian(std::size_t iteration) {
    const openvdb::Vec3f lower = mTarget.box().min().asVec3s() - openvdb::Vec3f(8.0f);
    const openvdb::Vec3f upper = mTarget.box().max().asVec3s() + openvdb::Vec3f(8.0f);
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, mParams.count(), 4096), Update(),
        [&](const tbb::blocked_range<std::size_t>& range, Update seen) {
            GaussianParameters gradient;
            seen.withGradient += mChunks.sumInto(mField, mParams, range.begin(), range.end(), gradient);
            if (mSettings.gradientHook) mSettings.gradientHook(iteration, range.begin(), gradient);
            std::vector<std::uint8_t> updated(range.size());
            mAdam->update(mParams, gradient, range.begin(), range.end(), updated.data());
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                if (!updated[i - range.begin()]) {
                    ++seen.kept;
                    continue;
                }
                repair(mParams, i, lower, upper);
                mField.reactivate(mParams, i);
            }
            return seen;
        },
        [](Update a, const Update& b) {
            a.withGradient += b.withGradient;
            a.kept += b.kept;
            return a;
        });
}

double FitLoop::heldOutPsnr(const SampleSet& heldOut) const {
    // The loss sums channels; PSNR uses the mean over channels.
    return psnrFromMse(weightedSquaredError(mField, heldOut, 1.0, nullptr, &mBins) / mTarget.channels(),
                       mTarget.peak());
}

void FitLoop::solveAmplitudesAtTheEnd(const std::vector<openvdb::Coord>& heldOutCoords, const SampleSet& heldOut,
                                      std::size_t iteration, const FitObserver& observer) {
    AmplitudeSolveSettings solve;
    solve.excluded = heldOutCoords;
    solve.iterations = mSettings.amplitudeSolveIterations;
    solve.cutoffSigmas = mSettings.cutoffSigmas;
    releaseTrainingState();
    if (mSettings.storedGeometry) mParams = mSettings.storedGeometry(mParams);
    if (mSettings.seconds > 0.0) solve.seconds = std::max(mSettings.seconds - elapsed() - closingSeconds(), 1e-9);
    if (observer) {  // each pass of the solve moves the bar on
        solve.afterPass = [&] {
            FitProgress pass;
            recordStanding(iteration, pass);
            observer(pass);
        };
    }
    mReport.amplitudeSolve = solveAmplitudes(mParams, mTarget, solve);
    if (!observer || mParams.count() == 0) return;
    mRebin = true;  // stored geometry may hold fewer Gaussians
    refreshField(iteration);
    FitProgress progress;
    recordStanding(iteration, progress);
    progress.heldOutEvaluated = true;
    progress.heldOutPsnr = heldOutPsnr(heldOut);
    observer(progress);
}

/// Frees what only Adam's steps need (the optimiser's moments, the gradient
/// chunks, the field and its bins, the drawn blocks) before the amplitude solve,
/// which builds a field of its own: that solve set the fit's peak memory
/// (docs/benchmarks.md, "A fit's memory").
/// refreshField() builds the field again for the held-out PSNR after it.
void FitLoop::releaseTrainingState() {
    mAdam.reset();
    mChunks = GradientChunks();
    mField.clear();
    mBins.clear();
    std::vector<SampledBlock>().swap(mBlocks);
    std::vector<BlockOutcome>().swap(mOutcomes);
    releaseFreedMemory();
}

GaussianParameters FitLoop::run(const FitObserver& observer, FitReport& report) {
    mObserver = observer;
    const SampleSet heldOut = voxelSampleSet(mTarget, mHeldOut);
    mPacing = mSettings.seconds > 0.0 && mSettings.minSamplesPerGaussian > 0.0 &&
              mSettings.schedule != SliceSchedule::SlicesOnly;
    // Timing a probe rather than the whole allowance keeps the peak memory near
    // what the time can train, not what the byte budget allows.
    initialise(mPacing ? std::min(mSettings.gaussians, kProbeGaussians) : mSettings.gaussians);
    mReport.setupSeconds = elapsed();

    std::size_t iteration = 0;
    bool finished = fractionDone(iteration) >= 1.0;
    double iterationStart = elapsed();
    while (mParams.count() > 0 && !finished) {
        const double fraction = fractionDone(iteration);
        FitProgress progress;
        progress.loss = step(iteration, fraction, progress);
        ++iteration;
        if (mPacing && ++mPaceIterations == kPaceIterations) fitCountToTheTime();

        if (mSettings.pruneEvery > 0 && iteration % mSettings.pruneEvery == 0 && !mOutcomes.empty()) {
            // Sites drawn for the purpose, not the blocks of the last batch, one site each:
            // those left a fit sites short, and its file above the ratio asked
            // (docs/benchmarks.md, "The file holds the ratio").
            const std::size_t negligible = negligibleCount(mParams, mSettings.pruneAmplitude);
            const PruneResult pruned =
                pruneAndRespawn(mParams, *mAdam, mSettings.pruneAmplitude,
                                largestResidualSites(negligible, streamSeed(mSettings.seed, kRespawns, iteration)));
            mReport.pruned += pruned.removed;
            mReport.respawned += pruned.respawned;
            mRebin = mRebin || pruned.removed > 0;
        }
        fillTheByteBudget(fractionDone(iteration));
        const double now = elapsed();
        mIterationSeconds = now - iterationStart;
        iterationStart = now;
        finished = lastIteration(iteration);
        recordStanding(iteration, progress);
        if (iteration % mSettings.logEvery == 0 || finished) {
            refreshField(iteration);
            progress.heldOutEvaluated = true;
            progress.heldOutPsnr = heldOutPsnr(heldOut);
        }
        if (observer) observer(progress);
    }
    mReport.iterations = iteration;
    mReport.adamSeconds = elapsed();
    if (iteration > 0) mReport.meanGradientShare /= double(iteration);
    mReport.amplitudeSolveSkipped = whyNotSolvingNow();
    if (mReport.amplitudeSolveSkipped.empty()) solveAmplitudesAtTheEnd(mHeldOut, heldOut, iteration, observer);
    mReport.seconds = elapsed();
    report = mReport;
    return std::move(mParams);
}

}  // namespace

double psnrFromMse(double mse, double peak) {
    if (mse <= 0.0) return std::numeric_limits<double>::infinity();
    // In logarithms, so that a peak of 1e300 does not square to infinity.
    return 20.0 * std::log10(peak) - 10.0 * std::log10(mse);
}

GaussianParameters fitGaussians(const VolumeTarget& target, const FitSettings& settings, const FitObserver& observer,
                                FitReport* report) {
    const std::string problem = settings.validate();
    if (!problem.empty()) throw InputError("fit settings", problem);
    FitReport ignored;
    FitLoop loop(target, settings);
    return loop.run(observer, report ? *report : ignored);
}

}  // namespace gvr
