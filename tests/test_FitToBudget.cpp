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

}  // namespace
}  // namespace gvr
