#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "pipeline/GaussianField.h"
#include "tests/ScopedEnvironment.h"
#include "tests/TestHelpers.h"
#include "workflow/TeamFit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace gvr {
namespace {

openvdb::GridBase::Ptr blobGrid() {
    return test::makeGrid({40, 24, 24}, [](int i, int j, int k) {
        const double x = i - 20.0, y = j - 12.0, z = k - 12.0;
        return float(20.0 + 200.0 * std::exp(-(x * x + y * y + z * z) / 90.0) + 30.0 * std::sin(0.4 * i));
    });
}

/// encodeAsset() of a copy (it records the format version it writes).
std::string fileBytes(GaussianAsset asset) { return encodeAsset(asset); }

BudgetedFitOptions iterationOptions() {
    BudgetedFitOptions options;
    options.settings.seconds = 0.0;
    options.settings.iterations = 12;
    options.gaussians = 200;
    return options;
}

TEST(TeamFit, AloneItMergesWhatTheBrickPartsWouldGive) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    const VolumeTarget target(grid, "blobs");
    const BudgetedFitOptions options = iterationOptions();
    std::vector<std::size_t> observed;
    const BrickObservers observers = [&](std::size_t brick) {
        observed.push_back(brick);
        return FitObserver{};
    };
    const TeamFitResult fit = fitAllBricks(SoloTeam(), grid, target, "blobs", options, {2, 4}, observers);

    // Parts as a job array's tasks write them and gvr merge reads them.
    const BrickPlan plan = planBrickedFit(target, "blobs", options, {2, 4});
    const auto part = [&](std::size_t b) {
        return decodeAsset(fileBytes(fitBrickPart(grid, "blobs", plan, b, 0.0)), "part");
    };
    const GaussianAsset merged = mergeBrickParts({part(0), part(1)}, {"0", "1"});
    EXPECT_EQ(fileBytes(fit.result.asset), fileBytes(merged));
    EXPECT_EQ(observed, (std::vector<std::size_t>{0, 1}));
    EXPECT_EQ(fit.owners, (std::vector<int>{0, 0}));
    ASSERT_EQ(fit.bricks.size(), 2u);
    for (std::size_t b = 0; b < 2; ++b) {
        EXPECT_EQ(fit.bricks[b].brick, b);
        EXPECT_EQ(fit.bricks[b].budget, plan.bricks[b].budget);
        EXPECT_EQ(fit.bricks[b].run.iterations, 12u);
        EXPECT_EQ(fit.bricks[b].run.rank, 0);
        EXPECT_GT(fit.bricks[b].run.rankPeakRssMiB, 0.0);
    }
    EXPECT_EQ(fit.result.fit.iterations, 24u);
}

TEST(TeamFit, AFailedBrickIsNamedWithItsRank) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    const VolumeTarget target(grid, "blobs");
    const test::ScopedEnvironment failBrick("GVR_TEST_FAIL_BRICK", "1");
    const std::string message = test::errorMessageOf<InputError>([&] {
        fitAllBricks(SoloTeam(), grid, target, "blobs", iterationOptions(), {2, 4});
    });
    EXPECT_NE(message.find("brick 1 (rank 0)"), std::string::npos) << message;
    EXPECT_NE(message.find("failed on purpose"), std::string::npos) << message;
}

TEST(TeamFit, MeasuredAcrossTheTeamItIsTheWholeVolumesMeasure) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    const VolumeTarget target(grid, "blobs");
    const SoloTeam team;
    const TeamFitResult fit = fitAllBricks(team, grid, target, "blobs", iterationOptions(), {2, 4});
    const std::string saved = fileBytes(fit.result.asset);
    const FieldAccuracy across = measureAcrossTeam(team, saved, target, fit);

    const GaussianAsset asset = decodeAsset(saved, "saved");
    const BrickSeams seams(fit.layout, kSeamWidth);
    const FieldAccuracy whole = measureFieldAccuracy(
        GaussianField(quantisedCopy(asset.params, asset.encoding), asset.cutoffSigmas), target, {},
        [&](const openvdb::Coord& ijk) { return seams.near(ijk); }, defaultExportCut(asset));
    EXPECT_NEAR(across.psnr, whole.psnr, 1e-9);
    EXPECT_NEAR(across.markedPsnr, whole.markedPsnr, 1e-9);
    EXPECT_EQ(across.markedVoxels, whole.markedVoxels);
    EXPECT_GT(across.markedVoxels, 0u);
}

TEST(TeamFit, OneBrickRecordsItsRunAndRefusesAnIndexBeyondTheCount) {
    const openvdb::GridBase::Ptr grid = blobGrid();
    const VolumeTarget target(grid, "blobs");
    const GaussianAsset part = fitOneBrick(grid, target, "blobs", iterationOptions(), {2, 4}, 1);
    EXPECT_EQ(brickOfPart(part, "part"), (std::pair<std::size_t, std::size_t>{1, 2}));
    const BrickRun run = brickRunOf(decodeAsset(fileBytes(part), "part"), "part");
    EXPECT_EQ(run.iterations, 12u);
    EXPECT_EQ(run.gaussians, part.params.count());

    const std::string beyond = test::errorMessageOf<InputError>([&] {
        fitOneBrick(grid, target, "blobs", iterationOptions(), {2, 4}, 2);
    });
    EXPECT_NE(beyond.find("`brick`: 2 is not below `of=2`"), std::string::npos) << beyond;

    GaussianAsset noRun = part;
    noRun.fitSettings["brick"].erase("run");
    EXPECT_NE(test::errorMessageOf<InputError>([&] {
                  brickRunOf(noRun, "old.part");
              }).find("old.part: corrupt brick run record"),
              std::string::npos);
}

}  // namespace
}  // namespace gvr
