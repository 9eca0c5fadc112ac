// The fit on synthetic volumes: it learns, it is reproducible, and hard inputs
// neither crash it nor fill it with NaN.

#include "pipeline/Error.h"
#include "pipeline/FieldAccuracy.h"
#include "pipeline/Fitter.h"
#include "pipeline/GaussianField.h"
#include "tests/TestHelpers.h"

#include <tbb/global_control.h>

#include <cmath>
#include <limits>

namespace gvr {
namespace {

FitSettings quickSettings(std::size_t gaussians, std::size_t iterations) {
    FitSettings settings;
    settings.gaussians = gaussians;
    settings.iterations = iterations;
    settings.seconds = 0.0;
    settings.voxelBatch = 4096;
    settings.slicePixels = 1024;
    settings.heldOutVoxels = 2048;
    settings.logEvery = 25;
    settings.pruneEvery = 50;
    return settings;
}

float blob(int i, int j, int k) {
    const float a = float((i - 10) * (i - 10) + (j - 12) * (j - 12) + (k - 8) * (k - 8));
    const float b = float((i - 22) * (i - 22) + (j - 8) * (j - 8) + (k - 14) * (k - 14));
    return 200.0f * std::exp(-a / 18.0f) + 120.0f * std::exp(-b / 8.0f);
}

TEST(Fitter, LearnsASmoothVolume) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    const GaussianField start(initialiseGaussians(target, {400, 0.6, 0.4, 1}), 3.0f);
    const double before = measureFieldAccuracy(start, target).psnr;
    std::vector<double> curve;
    const GaussianParameters params = fitGaussians(target, quickSettings(400, 400), [&](const FitProgress& p) {
        if (p.heldOutEvaluated) curve.push_back(p.heldOutPsnr);
    });
    const double after = measureFieldAccuracy(GaussianField(params, 3.0f), target).psnr;
    EXPECT_GT(after, before + 10.0) << "before " << before << " dB";
    EXPECT_GT(after, 35.0);
    EXPECT_EQ(curve.size(), 400u / 25u + 1u);  // and once after the amplitude solve
    EXPECT_GT(curve.back(), curve.front());
}

TEST(Fitter, TheAmplitudeSolveRunsOnTheStoredGeometry) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    FitSettings settings = quickSettings(60, 100);
    // Storage that rounds means to half voxels, far coarser than the asset's.
    settings.storedGeometry = [](const GaussianParameters& params) {
        GaussianParameters stored = params;
        for (float& m : stored.values[kMeans]) m = std::round(2.0f * m) / 2.0f;
        return stored;
    };
    FitReport report;
    const GaussianParameters params = fitGaussians(target, settings, {}, &report);
    for (float m : params.values[kMeans]) EXPECT_EQ(m, std::round(2.0f * m) / 2.0f);
    EXPECT_GT(report.amplitudeSolve.iterations, 0u);
    EXPECT_LT(report.amplitudeSolve.mseAfter, report.amplitudeSolve.mseBefore);
}

TEST(Fitter, ASkippedAmplitudeSolveSaysWhy) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    FitReport report;
    fitGaussians(target, quickSettings(60, 20), {}, &report);
    EXPECT_EQ(report.amplitudeSolveSkipped, "");

    FitSettings none = quickSettings(60, 20);
    none.amplitudeSolveIterations = 0;
    fitGaussians(target, none, {}, &report);
    EXPECT_EQ(report.amplitudeSolveSkipped, "no solve iterations were asked for");
    EXPECT_EQ(report.amplitudeSolve.iterations, 0u);

    FitSettings noShare = quickSettings(60, 0);
    noShare.seconds = 0.2;
    noShare.amplitudeSolveShare = 0.0;  // no time for even one dense pass
    fitGaussians(target, noShare, {}, &report);
    EXPECT_NE(
        report.amplitudeSolveSkipped.find("its share of the time budget, 0 s, holds fewer than the 3 dense passes"),
        std::string::npos)
        << report.amplitudeSolveSkipped;
    // So it is when the set-up outlasts the budget before any pass is timed (under the sanitizers, say).
    noShare.seconds = 1e-6;
    fitGaussians(target, noShare, {}, &report);
    EXPECT_NE(report.amplitudeSolveSkipped.find("its share of the time budget, 0 s"), std::string::npos)
        << report.amplitudeSolveSkipped;

    // A set-up that outlasts the budget, as on a loaded machine, leaves none for the solve.
    FitSettings spent = quickSettings(60, 0);
    spent.seconds = 1e-6;
    fitGaussians(target, spent, {}, &report);
    EXPECT_EQ(report.iterations, 0u);
    EXPECT_EQ(report.amplitudeSolveSkipped, "the time budget was spent before it");
    EXPECT_EQ(report.amplitudeSolve.seconds, 0.0);
}

TEST(Fitter, TheObserverHearsFromEveryPassOfTheAmplitudeSolve) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    const FitSettings settings = quickSettings(60, 20);
    std::size_t afterAdam = 0, lastIteration = 0;
    FitReport report;
    fitGaussians(
        target, settings,
        [&](const FitProgress& p) {
            if (p.iteration == settings.iterations && lastIteration == settings.iterations) ++afterAdam;
            lastIteration = p.iteration;
        },
        &report);
    // The first pass, one per iteration, the closing pass, then the held-out row.
    EXPECT_EQ(afterAdam, report.amplitudeSolve.iterations + 2 + 1);
}

TEST(Fitter, TheSetUpReportsItsProgressBeforeTheFirstIteration) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    std::vector<double> setUp;
    bool iterated = false, setUpAfterIterating = false;
    fitGaussians(target, quickSettings(60, 5), [&](const FitProgress& p) {
        if (p.setUp) {
            setUp.push_back(*p.setUp);
            setUpAfterIterating = setUpAfterIterating || iterated;
        } else {
            iterated = true;
        }
    });
    ASSERT_FALSE(setUp.empty());
    EXPECT_FALSE(setUpAfterIterating);
    EXPECT_TRUE(std::is_sorted(setUp.begin(), setUp.end()));
    EXPECT_EQ(setUp.back(), 1.0);
}

TEST(Fitter, SameSeedSameResultWhateverTheThreadCount) {
    const VolumeTarget target(test::makeGrid({24, 20, 16}, blob), "blobs");
    const FitSettings settings = quickSettings(150, 60);
    GaussianParameters serial, parallel;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        serial = fitGaussians(target, settings);
    }
    parallel = fitGaussians(target, settings);
    const GaussianParameters again = fitGaussians(target, settings);
    for (int g = 0; g < kGroupCount; ++g) {
        EXPECT_EQ(serial.values[g], parallel.values[g]) << groupName(ParameterGroup(g));
        EXPECT_EQ(parallel.values[g], again.values[g]) << groupName(ParameterGroup(g));
    }
    FitSettings other = settings;
    other.seed = 2;
    EXPECT_NE(fitGaussians(target, other).values[kMeans], parallel.values[kMeans]);
}

TEST(Fitter, EveryAblationRunsAndImproves) {
    const VolumeTarget target(test::makeGrid({24, 20, 16}, blob), "blobs");
    const double before =
        measureFieldAccuracy(GaussianField(initialiseGaussians(target, {150, 0.6, 0.4, 1}), 3.0f), target).psnr;
    for (Ablation ablation : {Ablation::Full, Ablation::A1, Ablation::A2, Ablation::A3, Ablation::A4, Ablation::A5}) {
        FitSettings settings = quickSettings(150, 120);
        applyAblation(ablation, settings);
        const GaussianParameters params = fitGaussians(target, settings);
        const double after = measureFieldAccuracy(GaussianField(params, 3.0f), target).psnr;
        EXPECT_GT(after, before) << ablationName(ablation);
    }
}

TEST(Fitter, ATimeBudgetTooShortForTheCountFitsFewerGaussians) {
    const VolumeTarget target(test::makeGrid({32, 28, 24}, blob), "blobs");
    FitSettings settings = quickSettings(2000, 0);
    settings.seconds = 1.5;
    settings.amplitudeSolveIterations = 0;
    settings.pruneEvery = 0;  // counts then change only by the time budget
    // 2000 Gaussians x 100,000 samples / 4096 per iteration: about 49,000 iterations,
    // which no machine runs in 1.5 s.
    settings.minSamplesPerGaussian = 100000.0;
    FitReport report;
    const GaussianParameters fewer = fitGaussians(target, settings, {}, &report);
    EXPECT_EQ(report.requestedGaussians, 2000u);
    EXPECT_LT(fewer.count(), 2000u / 2);
    EXPECT_GT(fewer.count(), 0u);
    EXPECT_TRUE(fewer.allFinite());

    settings.minSamplesPerGaussian = 0.0;  // the count as asked, however short the time
    const GaussianParameters asked = fitGaussians(target, settings, {}, &report);
    EXPECT_EQ(report.requestedGaussians, 0u);
    EXPECT_EQ(asked.count(), 2000u);
}

TEST(Fitter, RoomLeftInTheByteBudgetIsFilledWithGaussiansWhereTheResidualIsLargest) {
    const VolumeTarget target(
        test::makeGrid({48, 48, 48}, [](int i, int j, int k) { return float(i + j + k) + blob(i, j, k); }),
        "blobs on a ramp");
    FitSettings settings = quickSettings(2000, 100);
    settings.pruneEvery = 0;  // counts then change only by the fill
    settings.amplitudeSolveIterations = 0;
    std::vector<std::size_t> asked;
    settings.roomInBudget = [&](const GaussianParameters& params) {
        asked.push_back(params.count());
        return params.count() < 2500 ? 2500 - params.count() : std::size_t(0);
    };
    FitReport report;
    const GaussianParameters fitted = fitGaussians(target, settings, {}, &report);
    EXPECT_EQ(asked.size(), 2u);  // once at each fill point
    EXPECT_EQ(fitted.count(), 2500u);
    EXPECT_EQ(report.added, 500u);
    EXPECT_TRUE(fitted.allFinite());

    // Each added Gaussian starts at a voxel whose residual it holds: the fit is no
    // worse for them than the same fit without room.
    settings.roomInBudget = {};
    const GaussianParameters without = fitGaussians(target, settings);
    EXPECT_EQ(without.count(), 2000u);
    EXPECT_GT(measureFieldAccuracy(GaussianField(fitted, 3.0f), target).psnr,
              measureFieldAccuracy(GaussianField(without, 3.0f), target).psnr);
}

TEST(Fitter, ATimeBudgetThatCanTrainTheAllowanceGrowsPastTheProbe) {
    // The fit first times a probe of 16,384 Gaussians; one voxel sample each is
    // trained in a single iteration, so the time allows all 20,000. The probe must
    // end within half the budget, which 4 s left too tight under AddressSanitizer.
    const VolumeTarget target(
        test::makeGrid({64, 64, 64}, [](int i, int j, int k) { return float(i + j + k) + blob(i, j, k); }),
        "blobs on a ramp");
    ASSERT_GT(target.activeVoxelCount(), 20000u);
    FitSettings settings = quickSettings(20000, 0);
    settings.seconds = 10.0;
    settings.amplitudeSolveIterations = 0;
    settings.pruneEvery = 0;
    settings.minSamplesPerGaussian = 1.0;
    FitReport report;
    const GaussianParameters fitted = fitGaussians(target, settings, {}, &report);
    EXPECT_EQ(fitted.count(), 20000u);
    EXPECT_EQ(report.requestedGaussians, 0u);
}

TEST(Fitter, TheCountGrowsPastTheProbeInStepsThatKeepMemoryNearWhatIsTrained) {
    // An allowance of 150,000 that the time can train: from the probe's 16,384 the
    // count may grow at most 8x a step (131,072), then on to the allowance.
    const VolumeTarget target(
        test::makeGrid({64, 64, 64}, [](int i, int j, int k) { return float(i + j + k) + blob(i, j, k); }),
        "blobs on a ramp");
    FitSettings settings = quickSettings(150000, 0);
    settings.seconds = 12.0;
    settings.amplitudeSolveIterations = 0;
    settings.pruneEvery = 0;
    settings.minSamplesPerGaussian = 1.0;
    std::vector<std::size_t> counts;
    const FitObserver observer = [&](const FitProgress& p) {
        if (!p.setUp && (counts.empty() || counts.back() != p.gaussians)) counts.push_back(p.gaussians);
    };
    const GaussianParameters fitted = fitGaussians(target, settings, observer);
    ASSERT_GE(counts.size(), 2u);
    EXPECT_EQ(counts.front(), 16384u);
    for (std::size_t n = 1; n < counts.size(); ++n) EXPECT_LE(counts[n], 8 * counts[n - 1]) << n;
    // A third pace reaches the allowance where the machine is fast enough to start it
    // within half the budget (not always under AddressSanitizer).
    EXPECT_GE(fitted.count(), 8u * 16384u);
    EXPECT_LE(fitted.count(), 150000u);
}

TEST(Fitter, ANonFiniteGradientIsSkippedCountedAndForgotten) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blob), "blobs");
    FitSettings settings = quickSettings(300, 300);
    FitReport clean;
    const double cleanPsnr =
        measureFieldAccuracy(GaussianField(fitGaussians(target, settings, {}, &clean), 3.0f), target).psnr;
    EXPECT_EQ(clean.skippedSteps, 0u);
    // Early steps, a redraw of the voxel samples among them (every refreshEvery),
    // so that a residual kept from a bad step would reach the importance sampler.
    settings.gradientHook = [](std::size_t iteration, std::size_t first, GaussianParameters& gradient) {
        const float poison[] = {std::nanf(""), INFINITY, -INFINITY};
        if (first == 0 && iteration >= 10 && iteration < 13) {
            gradient.at(kMeans, iteration % gradient.count())[1] = poison[iteration - 10];
        }
    };
    FitReport injected;
    const GaussianParameters params = fitGaussians(target, settings, {}, &injected);
    EXPECT_EQ(injected.skippedSteps, 3u);
    ASSERT_TRUE(params.allFinite());
    const double psnr = measureFieldAccuracy(GaussianField(params, 3.0f), target).psnr;
    EXPECT_GT(psnr, cleanPsnr - 0.5) << "three skipped steps must cost almost nothing";
}

TEST(Fitter, InvalidSettingsAreRejected) {
    const VolumeTarget target(test::makeGrid({8, 8, 8}, blob), "blobs");
    FitSettings settings = quickSettings(10, 0);
    EXPECT_THROW(fitGaussians(target, settings), InputError);
    settings = quickSettings(10, 5);
    settings.importance.uniformShare = 1.5;
    EXPECT_THROW(fitGaussians(target, settings), InputError);
    // NaN passes every comparison: each number must be refused on its own.
    const double nan = std::nan("");
    for (double FitSettings::*field :
         {&FitSettings::sliceMax, &FitSettings::sliceGamma, &FitSettings::sliceBeta, &FitSettings::gradientSeedShare,
          &FitSettings::uniformSeedShare, &FitSettings::pruneAmplitude, &FitSettings::amplitudeSolveShare,
          &FitSettings::learningRate, &FitSettings::finalRateFactor, &FitSettings::seconds}) {
        settings = quickSettings(10, 5);
        settings.*field = nan;
        EXPECT_FALSE(settings.validate().empty()) << "a NaN setting was accepted";
    }
    for (double* value : {&settings.importance.uniformShare, &settings.importance.epsilon}) {
        settings = quickSettings(10, 5);
        *value = nan;
        EXPECT_FALSE(settings.validate().empty()) << "a NaN sampler setting was accepted";
    }
}

TEST(Fitter, BudgetsHaveAStatedMaximum) {
    // --time 1e30 was accepted and --iterations 2^64 - 1 ran forever.
    FitSettings settings = quickSettings(10, 0);
    settings.seconds = kMaxFitSeconds;
    EXPECT_EQ(settings.validate(), "");
    settings.seconds = 1e30;
    EXPECT_NE(settings.validate().find("`time` must lie in [0, 1000000] seconds"), std::string::npos);
    settings = quickSettings(10, 0);
    settings.iterations = kMaxFitIterations;
    EXPECT_EQ(settings.validate(), "");
    settings.iterations = std::numeric_limits<std::size_t>::max();
    EXPECT_NE(settings.validate().find("`iterations` must be at most 1000000000"), std::string::npos);
    settings = quickSettings(10, 5);
    settings.voxelBatch = kMaxVoxelBatch + 1;
    EXPECT_NE(settings.validate().find("`batch`"), std::string::npos);
}

struct HardVolume {
    const char* name;
    std::array<int, 3> dims;
    std::function<float(int, int, int)> value;
    openvdb::Vec3d spacing;
    std::optional<double> threshold;  ///< ingest's --threshold; unset: the minimum is inactive
    double minPsnr;                   ///< whole-volume dB that 200 Gaussians must reach in 400 iterations
};

/// ctest lists the case by name rather than as raw bytes.
void PrintTo(const HardVolume& volume, std::ostream* out) { *out << volume.name; }

class HardVolumes : public ::testing::TestWithParam<HardVolume> {};

TEST_P(HardVolumes, AreFittedWithoutSkippedSteps) {
    const HardVolume& hard = GetParam();
    const VolumeTarget target(test::makeGrid(hard.dims, hard.value, hard.spacing, hard.threshold), hard.name);
    ASSERT_GT(target.activeVoxelCount(), 0u) << "a case with nothing active tests nothing";
    FitReport report;
    const GaussianParameters params = fitGaussians(target, quickSettings(200, 400), {}, &report);
    EXPECT_TRUE(params.allFinite());
    EXPECT_LE(params.count(), 200u);
    EXPECT_EQ(report.skippedSteps, 0u);
    const FieldAccuracy error = measureFieldAccuracy(GaussianField(params, 3.0f), target);
    EXPECT_GE(error.psnr, hard.minPsnr);
}

float ball(int i, int j, int k, float radius) {
    return float((i - 10) * (i - 10) + (j - 10) * (j - 10) + (k - 6) * (k - 6)) < radius * radius ? 1.0f : 0.0f;
}

INSTANTIATE_TEST_SUITE_P(
    Stiff, HardVolumes,
    ::testing::Values(
        // A zero data range: every voxel is active and the fit must be exact, not NaN.
        HardVolume{"constant_all_active", {16, 16, 16}, [](int, int, int) { return 7.0f; }, {1, 1, 1}, 0.0, 30.0},
        HardVolume{"one_voxel_volume", {1, 1, 1}, [](int, int, int) { return 5.0f; }, {1, 1, 1}, 0.0, 30.0},
        HardVolume{"single_bright_voxel",
                   {16, 16, 16},
                   [](int i, int j, int k) { return i == 8 && j == 8 && k == 8 ? 1000.0f : 0.0f; },
                   {1, 1, 1},
                   {},
                   30.0},
        HardVolume{"hounsfield_with_minus_3024_padding",
                   {20, 20, 12},
                   [](int i, int j, int k) {
                       return ball(i, j, k, 9.0f) > 0 ? -1000.0f + 2400.0f * ball(i, j, k, 4.0f) : -3024.0f;
                   },
                   {1, 1, 1},
                   {},
                   21.0},
        // The outlier sits outside the held-out voxels (a tenth of this small box), which training never sees.
        HardVolume{"float_with_one_1e6_outlier",
                   {20, 20, 12},
                   [](int i, int j, int k) { return i == 15 && j == 12 && k == 7 ? 1e6f : blob(i, j, k); },
                   {1, 1, 1},
                   {},
                   40.0},
        HardVolume{"float_1e-3_to_1e6",
                   {20, 20, 12},
                   [](int i, int j, int k) { return float(std::pow(10.0, -3.0 + 9.0 * ((i + j + k) % 10) / 9.0)); },
                   {1, 1, 1},
                   {},
                   11.0},
        HardVolume{"anisotropic_0.3x0.3x5", {24, 24, 6}, blob, {0.3, 0.3, 5.0}, {}, 45.0},
        HardVolume{"needle",
                   {32, 8, 8},
                   [](int i, int j, int k) { return j == 4 && k == 4 ? 100.0f + i : 0.0f; },
                   {1, 1, 1},
                   {},
                   32.0},
        HardVolume{"sheet",
                   {24, 24, 8},
                   [](int i, int j, int k) { return k == 4 ? 50.0f + float(i + j) : 0.0f; },
                   {1, 1, 1},
                   {},
                   26.0}),
    [](const ::testing::TestParamInfo<HardVolume>& info) {
        std::string name = info.param.name;
        for (char& c : name)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
        return name;
    });

TEST(Fitter, AnEmptyVolumeGivesNoGaussians) {
    const VolumeTarget target(test::makeGrid({8, 8, 8}, [](int, int, int) { return 0.0f; }), "zeros");
    EXPECT_EQ(target.activeVoxelCount(), 0u);
    EXPECT_EQ(fitGaussians(target, quickSettings(50, 10)).count(), 0u);
}

}  // namespace
}  // namespace gvr
