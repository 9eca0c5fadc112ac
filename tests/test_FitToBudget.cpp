#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"
#include "workflow/FitToBudget.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

openvdb::GridBase::Ptr blobGrid() {
    return test::makeGrid({40, 32, 24}, [](int i, int j, int k) {
        const double r2 = (i - 19.5) * (i - 19.5) + (j - 15.5) * (j - 15.5) + (k - 11.5) * (k - 11.5);
        return float(200.0 * std::exp(-r2 / 60.0));
    });
}

BudgetedFitOptions iterationOptions(std::size_t iterations) {
    BudgetedFitOptions options;
    options.settings.seconds = 0.0;
    options.settings.iterations = iterations;
    return options;
}

TEST(Compress, KeepsTheAssetWithinTheRatioBudget) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    BudgetedFitOptions options = iterationOptions(20);
    options.ratio = 10.0;
    const BudgetedFitResult result = fitToBudget(grid, "blobs", options);
    const double rawBytes = double(readVolumeMetadata(*grid)->rawSourceBytes());
    EXPECT_EQ(result.maxBytes, std::uint64_t(rawBytes / 10.0));
    EXPECT_GT(result.asset.params.count(), 0u);
    EXPECT_LE(assetFileBytes(result.asset), result.maxBytes);
}

TEST(Compress, TheCodedFileIsTheAssetWithinItsBudget) {
    BudgetedFitOptions options = iterationOptions(20);
    options.ratio = 10.0;
    const BudgetedFitResult result = fitToBudget(blobGrid(), "blobs", options);
    EXPECT_LE(result.file.size(), result.maxBytes);
    const GaussianAsset decoded = decodeAsset(result.file, "blobs.gvr");
    ASSERT_EQ(decoded.params.count(), result.asset.params.count());
    EXPECT_EQ(decoded.params.values, quantisedCopy(result.asset.params, result.asset.encoding).values);
}

TEST(Compress, StopsAtTheIterationAfterTheCancelFlagIsSet) {
    std::atomic<bool> cancel{false};
    BudgetedFitOptions options = iterationOptions(1000);
    options.cancel = &cancel;
    std::size_t lastIteration = 0;
    const FitObserver observer = [&](const FitProgress& progress) {
        lastIteration = progress.iteration;
        if (progress.iteration == 3) cancel = true;
    };
    EXPECT_THROW(fitToBudget(blobGrid(), "blobs", options, observer), Cancelled);
    EXPECT_EQ(lastIteration, 3u);
}

TEST(Compress, ACancelFlagSetBeforehandStopsBeforeAnyIteration) {
    std::atomic<bool> cancel{true};
    BudgetedFitOptions options = iterationOptions(1000);
    options.cancel = &cancel;
    bool observed = false;
    EXPECT_THROW(fitToBudget(blobGrid(), "blobs", options, [&](const FitProgress&) { observed = true; }), Cancelled);
    EXPECT_FALSE(observed);
}

TEST(Compress, AnUnsetCancelFlagChangesNothing) {
    std::atomic<bool> cancel{false};
    BudgetedFitOptions watched = iterationOptions(15);
    watched.cancel = &cancel;
    const BudgetedFitResult a = fitToBudget(blobGrid(), "blobs", iterationOptions(15));
    const BudgetedFitResult b = fitToBudget(blobGrid(), "blobs", watched);
    ASSERT_EQ(a.asset.params.count(), b.asset.params.count());
    EXPECT_EQ(a.asset.params.values, b.asset.params.values);
    EXPECT_EQ(a.fit.iterations, 15u);
    EXPECT_EQ(b.fit.iterations, 15u);
}

TEST(Compress, RefusesLabelsWithoutALabelGrid) {
    BudgetedFitOptions options = iterationOptions(5);
    options.labels = "all";
    EXPECT_THROW(fitToBudget(blobGrid(), "blobs", options), InputError);
}

TEST(Compress, ATimeBudgetKeepsEveryGaussianTheRatioAllows) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    BudgetedFitOptions options;
    options.ratio = 10.0;
    options.settings.seconds = 0.5;  // far too short to train them: the count stays all the same
    const BudgetedFitResult result = fitToBudget(grid, "blobs", options);
    EXPECT_EQ(result.fit.requestedGaussians, 0u);
    EXPECT_LE(double(assetFileBytes(result.asset)), double(result.maxBytes));
    // The count it started from is the ratio's, however many iterations the machine
    // ran in the time (none, under the sanitizers): those only add where there is room.
    std::uint64_t maxBytes = 0;
    const GaussianAsset skeleton =
        assetSkeleton(VolumeTarget(grid, "blobs"), checkedSettings(options), options, "blobs");
    const std::size_t allowed = budgetedGaussians(skeleton, options, maxBytes);
    EXPECT_EQ(maxBytes, result.maxBytes);
    EXPECT_EQ(result.asset.params.count() + result.dropped - result.fit.added, allowed);
}

BudgetedFitResult fitOf(std::size_t gaussians, double samples) {
    BudgetedFitResult result;
    result.asset.params = GaussianParameters(gaussians, 1);
    result.fit.iterations = 10;
    result.fit.voxelSamples = samples;
    result.fit.setupSeconds = 1.0;
    result.fit.adamSeconds = 11.0;  // 10 s of iterations
    return result;
}

TEST(Compress, AnUndertrainedFitSaysSoWithTheTimeThatWouldTrainIt) {
    FitSettings settings;
    settings.seconds = 12.0;
    // 100 samples each: ten times the iterations' 10 s more, 12 + 90 = 102 s, shown as 110.
    const std::string note = undertrainedNote(fitOf(1000, 100000.0), settings, "--min-samples");
    EXPECT_NE(note.find("each of the 1000 Gaussians about 100 voxel samples"), std::string::npos) << note;
    EXPECT_NE(note.find("about 110 s would give each 1000"), std::string::npos) << note;
    EXPECT_NE(note.find("(--min-samples 1000 "), std::string::npos) << note;
    EXPECT_EQ(note.find('\n'), std::string::npos);
    EXPECT_NE(undertrainedNote(fitOf(1000, 100000.0), settings, "min_samples=").find("(min_samples=1000 "),
              std::string::npos);

    EXPECT_EQ(undertrainedNote(fitOf(1000, 2e6), settings, "--min-samples"), "");  // 2000 each: trained
    BudgetedFitResult seeded = fitOf(1000, 0.0);
    seeded.fit.iterations = 0;  // a loaded machine's set-up can outlast a short budget
    seeded.fit.setupSeconds = 14.0;
    EXPECT_EQ(undertrainedNote(seeded, settings, "--min-samples"),
              "undertrained: the 12.0 s budget ended before the first iteration, the set-up alone taking 14.0 s; "
              "the 1000 Gaussians are as seeded");
    settings.seconds = 0.0;  // an iteration budget: the user chose the work, not the time
    settings.iterations = 10;
    EXPECT_EQ(undertrainedNote(fitOf(1000, 100000.0), settings, "--min-samples"), "");
}

}  // namespace
}  // namespace gvr
