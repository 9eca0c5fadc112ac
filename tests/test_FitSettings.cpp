// A fit's settings: what validate() refuses (NaN included), the ablation table and
// its names, and the slice curriculum's weight over the budget.

#include "pipeline/Error.h"
#include "pipeline/FitSettings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace gvr {
namespace {

/// Defaults plus an iteration budget: valid, so each test breaks one thing.
FitSettings valid() {
    FitSettings settings;
    settings.iterations = 10;
    return settings;
}

bool mentions(const std::string& message, const std::string& flag) { return message.find(flag) != std::string::npos; }

TEST(FitSettings, DefaultsNeedOnlyABudget) {
    EXPECT_TRUE(mentions(FitSettings().validate(), "`iterations` or `time`"));
    EXPECT_EQ(valid().validate(), "");
    FitSettings timed;
    timed.seconds = 2.5;
    EXPECT_EQ(timed.validate(), "");
}

TEST(FitSettings, NegativeOrNaNTimeIsRefused) {
    FitSettings settings = valid();
    settings.seconds = -1.0;
    EXPECT_TRUE(mentions(settings.validate(), "`time`"));
    settings.seconds = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(mentions(settings.validate(), "`time`"));
    settings.seconds = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(mentions(settings.validate(), "`time`"));
}

TEST(FitSettings, SeedSharesMustNotBothBeZeroOrInfinite) {
    FitSettings settings = valid();
    settings.gradientSeedShare = 0.0;
    EXPECT_EQ(settings.validate(), "");
    settings.uniformSeedShare = 0.0;
    EXPECT_TRUE(mentions(settings.validate(), "`gradient_share`"));
    settings = valid();
    settings.gradientSeedShare = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(mentions(settings.validate(), "`gradient_share`"));
    settings = valid();
    settings.uniformSeedShare = -0.1;
    EXPECT_TRUE(mentions(settings.validate(), "`gradient_share`"));
}

TEST(FitSettings, ZeroSlicePixelsOnlyWhereUnused) {
    FitSettings settings = valid();
    settings.slicePixels = 0;
    EXPECT_TRUE(mentions(settings.validate(), "`slice_pixels`"));
    settings.schedule = SliceSchedule::None;
    EXPECT_EQ(settings.validate(), "");
}

TEST(FitSettings, RangeEdgesAreInclusiveWhereDocumented) {
    FitSettings settings = valid();
    settings.rowStride = 64;
    EXPECT_EQ(settings.validate(), "");
    settings.rowStride = 65;
    EXPECT_TRUE(mentions(settings.validate(), "`row_stride`"));
    settings.rowStride = 0;
    EXPECT_TRUE(mentions(settings.validate(), "`row_stride`"));

    settings = valid();
    settings.finalRateFactor = 1.0;
    EXPECT_EQ(settings.validate(), "");
    settings.finalRateFactor = 1.5;
    EXPECT_TRUE(mentions(settings.validate(), "`lr_final`"));

    settings = valid();
    settings.cutoffSigmas = 10.0f;
    EXPECT_EQ(settings.validate(), "");
    settings.cutoffSigmas = 0.5f;
    EXPECT_TRUE(mentions(settings.validate(), "`cutoff`"));
    settings.cutoffSigmas = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(mentions(settings.validate(), "`cutoff`"));

    settings = valid();
    settings.amplitudeSolveShare = 1.0;  // all the time for the solve would leave none for Adam
    EXPECT_TRUE(mentions(settings.validate(), "`solve_share`"));

    settings = valid();
    settings.heldOutVoxels = 0;
    EXPECT_TRUE(mentions(settings.validate(), "`held_out`"));

    settings = valid();
    settings.sliceGamma = -5.0;  // any finite point of the budget is a valid midpoint
    EXPECT_EQ(settings.validate(), "");
}

TEST(FitSettings, AblationNamesRoundTrip) {
    for (Ablation a : {Ablation::Full, Ablation::A1, Ablation::A2, Ablation::A3, Ablation::A4, Ablation::A5}) {
        EXPECT_EQ(ablationFromName(ablationName(a)), a) << ablationName(a);
    }
    EXPECT_EQ(ablationName(Ablation::Full), "full");
    EXPECT_EQ(ablationName(Ablation::A3), "A3");
}

TEST(FitSettings, UnknownAblationNamesThrow) {
    // Names are matched exactly: "a1" and "Full" are not the flags' spellings.
    for (const char* name : {"a1", "Full", "A6", ""}) EXPECT_THROW(ablationFromName(name), InputError) << name;
    try {
        ablationFromName("A6");
        ADD_FAILURE() << "A6 was accepted";
    } catch (const InputError& error) {
        EXPECT_TRUE(mentions(error.what(), "'A6'")) << error.what();
    }
}

TEST(FitSettings, AblationTable) {
    FitSettings settings;
    applyAblation(Ablation::A1, settings);
    EXPECT_FALSE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::None);
    applyAblation(Ablation::A2, settings);
    EXPECT_FALSE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::VoxelsThenSlices);
    applyAblation(Ablation::A3, settings);
    EXPECT_TRUE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::SlicesThenVoxels);
    applyAblation(Ablation::A5, settings);
    EXPECT_TRUE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::None);
    // Slices only never draws voxels, so A4 leaves the voxel sampler as it was.
    settings.importanceSampling = false;
    applyAblation(Ablation::A4, settings);
    EXPECT_FALSE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::SlicesOnly);
    applyAblation(Ablation::Full, settings);
    EXPECT_TRUE(settings.importanceSampling);
    EXPECT_EQ(settings.schedule, SliceSchedule::VoxelsThenSlices);
}

TEST(FitSettings, SliceWeightOneBetaPastTheMidpoint) {
    FitSettings settings;
    const double t = settings.sliceGamma + settings.sliceBeta;
    EXPECT_NEAR(sliceWeight(settings, t), settings.sliceMax / (1.0 + std::exp(-1.0)), 1e-12);
}

TEST(FitSettings, SliceWeightSaturatesWithoutNaNFarOutsideTheBudget) {
    // exp overflows to infinity out here; the logistic must still give 0 or its limit.
    FitSettings settings;
    EXPECT_EQ(sliceWeight(settings, -1e9), 0.0);
    EXPECT_DOUBLE_EQ(sliceWeight(settings, 1e9), settings.sliceMax);
    settings.schedule = SliceSchedule::SlicesThenVoxels;
    EXPECT_DOUBLE_EQ(sliceWeight(settings, -1e9), 1.0);
    EXPECT_EQ(sliceWeight(settings, 1e9), 0.0);
}

TEST(FitSettings, CurriculumWeightsFollowTheSchedule) {
    FitSettings settings;
    EXPECT_NEAR(sliceWeight(settings, settings.sliceGamma), 0.5 * settings.sliceMax, 1e-12);
    EXPECT_LT(sliceWeight(settings, 0.0), 0.01 * settings.sliceMax);
    EXPECT_GT(sliceWeight(settings, 1.0), 0.99 * settings.sliceMax);
    applyAblation(Ablation::A3, settings);
    EXPECT_GT(sliceWeight(settings, 0.0), 0.99);
    applyAblation(Ablation::A4, settings);
    EXPECT_EQ(sliceWeight(settings, 0.3), 1.0);
    applyAblation(Ablation::A5, settings);
    EXPECT_EQ(sliceWeight(settings, 0.9), 0.0);
}

TEST(FitSettings, TheSlicePassWaitsForOnePercentOfItsMaximumWeight) {
    FitSettings settings;  // voxels then slices: 0.1 sigmoid((t - 0.5) / 0.08)
    const double onePercent = settings.sliceGamma + settings.sliceBeta * std::log(0.01 / 0.99);  // about 0.132
    EXPECT_FALSE(slicePassRuns(settings, 0.0));
    EXPECT_FALSE(slicePassRuns(settings, onePercent - 0.002));
    EXPECT_TRUE(slicePassRuns(settings, onePercent + 0.002));
    EXPECT_TRUE(slicePassRuns(settings, 1.0));
    settings.schedule = SliceSchedule::None;
    EXPECT_FALSE(slicePassRuns(settings, 1.0));
    settings.schedule = SliceSchedule::SlicesOnly;
    EXPECT_TRUE(slicePassRuns(settings, 0.0));
}

TEST(FitSettings, TheDefaultBatchGrowsWithTheCountFromItsLeast) {
    FitSettings settings = valid();
    settings.voxelBatch = 0;
    EXPECT_EQ(settings.batchFor(1000), kLeastVoxelBatch);
    EXPECT_EQ(settings.batchFor(480000), std::size_t(kBatchPerGaussian * 480000));
    EXPECT_EQ(settings.batchFor(std::size_t(1) << 40), kMaxVoxelBatch);  // never past what validate() allows
    settings.voxelBatch = 4096;                                          // a batch asked for is kept whatever the count
    EXPECT_EQ(settings.batchFor(480000), 4096u);
    EXPECT_EQ(settings.validate(), "");
}

TEST(FitSettings, TheRatioIsKeptUnlessTheUserTradesGaussiansForTraining) {
    EXPECT_EQ(FitSettings{}.minSamplesPerGaussian, 0.0);
}

}  // namespace
}  // namespace gvr
