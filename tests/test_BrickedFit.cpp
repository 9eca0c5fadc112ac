// A fit cut into bricks: the plan every process makes alike, each process's share
// of its time, the records a part carries, and the merge of the parts.

#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"
#include "workflow/BrickedFit.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace gvr {
namespace {

/// Two bricks of a 40 x 24 x 24 blob volume, @a gaussians fitted for @a iterations.
BudgetedFitOptions twoBrickOptions(std::size_t gaussians, std::size_t iterations) {
    BudgetedFitOptions options;
    options.settings.seconds = 0.0;
    options.settings.iterations = iterations;
    options.gaussians = gaussians;
    return options;
}

std::string planRefusal(const VolumeTarget& target, const BudgetedFitOptions& options, const BrickOptions& bricks) {
    return test::errorMessageOf<InputError>([&] { planBrickedFit(target, "blobs", options, bricks); });
}

TEST(BrickedFit, PlanSplitsTheCountAndRecordsTheBricksInTheSkeleton) {
    const VolumeTarget target(test::blobGrid({40, 24, 24}), "blobs");
    const BrickPlan plan = planBrickedFit(target, "blobs", twoBrickOptions(200, 15), {2, 4});
    ASSERT_EQ(plan.bricks.size(), 2u);
    EXPECT_EQ(plan.lattice, openvdb::Coord(2, 1, 1));  // across the long axis
    EXPECT_EQ(plan.halo, 4);
    EXPECT_EQ(plan.maxBytes, 0u);  // an exact count, not a byte budget
    EXPECT_EQ(plan.settings.gaussians, 200u);
    EXPECT_EQ(plan.bricks[0].budget + plan.bricks[1].budget, 200u);
    const nlohmann::json& record = plan.skeleton.fitSettings.at("bricks");
    EXPECT_EQ(record.at("count"), 2);
    EXPECT_EQ(record.at("lattice"), nlohmann::json::array({2, 1, 1}));
    EXPECT_EQ(record.at("halo"), 4);
}

TEST(BrickedFit, PlanRefusesBadBrickOptionsNamingTheSetting) {
    const VolumeTarget target(test::blobGrid({40, 24, 24}), "blobs");
    const BudgetedFitOptions options = twoBrickOptions(200, 15);
    EXPECT_EQ(planRefusal(target, options, {0, 4}), "`bricks`: must be at least 1");
    EXPECT_EQ(planRefusal(target, options, {2, -1}), "`halo`: must be at least 0");
    BudgetedFitOptions labelled = options;
    labelled.labels = "all";
    EXPECT_EQ(planRefusal(target, labelled, {2, 4}), "`bricks`: cannot be combined with `labels`");
    // 5 x 3 x 3 leaves cannot make 64 bricks.
    EXPECT_NE(planRefusal(target, options, {64, 4}).find("`bricks`"), std::string::npos);
}

TEST(BrickedFit, EachBrickGetsItsShareOfTheTimeByGaussians) {
    const VolumeTarget target(test::blobGrid({40, 24, 24}), "blobs");
    BrickPlan plan = planBrickedFit(target, "blobs", twoBrickOptions(200, 15), {2, 4});
    plan.settings.seconds = 8.0;
    plan.bricks[0].budget = 30;
    plan.bricks[1].budget = 10;
    EXPECT_DOUBLE_EQ(brickSeconds(plan, {0, 1}, 0), 6.0);
    EXPECT_DOUBLE_EQ(brickSeconds(plan, {0, 1}, 1), 2.0);
    EXPECT_DOUBLE_EQ(brickSeconds(plan, {1}, 1), 8.0);  // alone, a brick has all of it
    plan.bricks[0].budget = plan.bricks[1].budget = 0;
    EXPECT_EQ(brickSeconds(plan, {0, 1}, 0), 0.0);
}

TEST(BrickedFit, APartRecordsItsBrickItsRunAndAFineEncoding) {
    const openvdb::GridBase::Ptr grid = test::blobGrid({40, 24, 24});
    const VolumeTarget target(grid, "blobs");
    const BrickPlan plan = planBrickedFit(target, "blobs", twoBrickOptions(100, 5), {2, 4});
    const GaussianAsset part = fitBrickPart(grid, "blobs", plan, 1, 0.0, {}, /*rank=*/3);
    EXPECT_EQ(brickOfPart(part, "p1"), std::make_pair(std::size_t(1), std::size_t(2)));
    const BrickRun run = brickRunOf(part, "p1");
    EXPECT_EQ(run.rank, 3);
    EXPECT_EQ(run.iterations, 5u);
    EXPECT_EQ(run.gaussians, part.params.count());
    // Finer than any asset's own, so that the merge's rounding decides the result.
    EXPECT_EQ(part.encoding.meanStep, 1.0f / 512.0f);
    EXPECT_EQ(part.encoding.amplitudeBits, 16);
}

TEST(BrickedFit, RunRecordsReadBackInTheKeysPartsHaveAlwaysHad) {
    // gvr merge reads parts that earlier versions wrote.
    GaussianAsset part;
    part.fitSettings["brick"] = {{"index", 0}, {"of", 2}};
    part.fitSettings["brick"]["run"] = {{"rank", 2},
                                        {"gaussians", 40},
                                        {"iterations", 7},
                                        {"seconds", 1.5},
                                        {"pruned", 3},
                                        {"respawned", 1},
                                        {"solve_iterations", 9},
                                        {"solve_seconds", 0.25},
                                        {"rank_peak_rss_mib", 512.0}};
    const BrickRun run = brickRunOf(part, "p0");
    EXPECT_EQ(run.rank, 2);
    EXPECT_EQ(run.gaussians, 40u);
    EXPECT_EQ(run.iterations, 7u);
    EXPECT_EQ(run.seconds, 1.5);
    EXPECT_EQ(run.pruned, 3u);
    EXPECT_EQ(run.respawned, 1u);
    EXPECT_EQ(run.solveIterations, 9u);
    EXPECT_EQ(run.solveSeconds, 0.25);
    EXPECT_EQ(run.rankPeakRssMiB, 512.0);
}

TEST(BrickedFit, MissingOrCorruptRecordsAreRefusedNamingThePart) {
    const GaussianAsset whole{};
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { brickOfPart(whole, "whole.gvr"); }),
              "whole.gvr: is not a brick part (the asset of one brick of a bricked fit)");
    EXPECT_EQ(test::errorMessageOf<InputError>([&] {
                  brickRunOf(whole, "whole.gvr");
              }).rfind("whole.gvr: corrupt brick run record: ", 0),
              0u);
    GaussianAsset corrupt;
    corrupt.fitSettings["brick"] = {{"index", "one"}, {"of", 2}};
    EXPECT_EQ(test::errorMessageOf<InputError>([&] {
                  brickOfPart(corrupt, "bad.gvr");
              }).rfind("bad.gvr: corrupt brick record: ", 0),
              0u);
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { mergeBrickParts({}, {}); }), "merge: no parts given");
}

TEST(BrickedFit, MergeIsTheSameWhateverTheOrderOfTheParts) {
    const openvdb::GridBase::Ptr grid = test::blobGrid({40, 24, 24});
    const VolumeTarget target(grid, "blobs");
    const BrickPlan plan = planBrickedFit(target, "blobs", twoBrickOptions(200, 15), {2, 4});
    std::vector<GaussianAsset> parts;
    for (std::size_t b = 0; b < plan.bricks.size(); ++b) parts.push_back(fitBrickPart(grid, "blobs", plan, b, 0.0));
    GaussianAsset forward = mergeBrickParts(parts, {"a", "b"});
    GaussianAsset backward = mergeBrickParts({parts[1], parts[0]}, {"b", "a"});
    EXPECT_EQ(forward.params.count(), 200u);
    EXPECT_EQ(encodeAsset(forward), encodeAsset(backward));
    EXPECT_FALSE(forward.fitSettings.contains("brick"));
    EXPECT_EQ(forward.fitSettings.at("bricks").at("count"), 2);
}

TEST(BrickedFit, MergeRefusesMissingRepeatedAndForeignParts) {
    const openvdb::GridBase::Ptr grid = test::blobGrid({40, 24, 24});
    const VolumeTarget target(grid, "blobs");
    BudgetedFitOptions options = twoBrickOptions(100, 5);
    const BrickPlan plan = planBrickedFit(target, "blobs", options, {2, 4});
    const GaussianAsset first = fitBrickPart(grid, "blobs", plan, 0, 0.0);
    const GaussianAsset second = fitBrickPart(grid, "blobs", plan, 1, 0.0);
    const auto refusal = [](std::vector<GaussianAsset> parts, std::vector<std::string> names) {
        try {
            mergeBrickParts(std::move(parts), names);
        } catch (const InputError& error) {
            return std::string(error.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(refusal({first}, {"p0"}).find("bricks 1 of 2 are missing"), std::string::npos);
    EXPECT_NE(refusal({first, first}, {"p0", "again"}).find("again: repeats brick 0"), std::string::npos);
    options.settings.seed = 7;
    const BrickPlan other = planBrickedFit(target, "blobs", options, {2, 4});
    EXPECT_NE(refusal({first, fitBrickPart(grid, "blobs", other, 1, 0.0)}, {"p0", "seed7"})
                  .find("seed7: is a brick of another fit"),
              std::string::npos);
    // The cutoff is the asset's, not a setting the fit records: parts of two once merged under the first's.
    options.settings.seed = BudgetedFitOptions().settings.seed;
    options.settings.cutoffSigmas = 4.0f;
    const BrickPlan wider = planBrickedFit(target, "blobs", options, {2, 4});
    EXPECT_NE(refusal({first, fitBrickPart(grid, "blobs", wider, 1, 0.0)}, {"p0", "cutoff4"})
                  .find("cutoff4: is a brick of another fit"),
              std::string::npos);
    // Parts of fits at other ratios once merged without a word.
    BudgetedFitOptions tenToOne = twoBrickOptions(0, 5), twentyToOne = twoBrickOptions(0, 5);
    tenToOne.ratio = 10.0;
    twentyToOne.ratio = 20.0;
    const BrickPlan ten = planBrickedFit(target, "blobs", tenToOne, {2, 4});
    const BrickPlan twenty = planBrickedFit(target, "blobs", twentyToOne, {2, 4});
    EXPECT_NE(
        refusal({fitBrickPart(grid, "blobs", ten, 0, 0.0), fitBrickPart(grid, "blobs", twenty, 1, 0.0)}, {"p0", "p1"})
            .find("p1: is a brick of another fit"),
        std::string::npos);
    GaussianAsset whole = first;
    whole.fitSettings.erase("brick");
    EXPECT_NE(refusal({whole, second}, {"whole", "p1"}).find("whole: is not a brick part"), std::string::npos);
}

}  // namespace
}  // namespace gvr
