// gvr fit --bricks, --brick I --of N and gvr merge, as a user runs them.

#include "tests/ScopedEnvironment.h"
#include "tests/TestHelpers.h"

#include <nlohmann/json.hpp>

#include <cstdlib>

namespace gvr {
namespace {

TEST(CliBricks, PartsMergedAreByteForByteTheBrickedFit) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string common = "fit -q '" + grid + "' --gaussians 150 --iterations 30 --seed 5 --batch 2048 ";
    const test::CommandResult whole =
        test::runGvr(common + "--bricks 3 --json -o '" + dir.path("whole.gvr") + "'", dir);
    ASSERT_EQ(whole.exitCode, 0) << whole.err;
    const nlohmann::json report = nlohmann::json::parse(whole.out);
    EXPECT_EQ(report["bricks"].size(), 3u);
    EXPECT_EQ(report["gaussians"], 150);
    EXPECT_GT(report["seam_voxels"].get<int>(), 0);

    std::string parts;
    for (int b : {2, 0, 1}) {  // any order, as a job array finishes
        const std::string part = dir.path("part" + std::to_string(b) + ".gvr");
        const test::CommandResult run =
            test::runGvr(common + "--brick " + std::to_string(b) + " --of 3 -o '" + part + "'", dir);
        ASSERT_EQ(run.exitCode, 0) << run.err;
        EXPECT_NE(run.out.find("gvr merge"), std::string::npos) << run.out;
        parts += " '" + part + "'";
    }
    const test::CommandResult merged = test::runGvr("merge" + parts + " -o '" + dir.path("merged.gvr") + "'", dir);
    ASSERT_EQ(merged.exitCode, 0) << merged.err;
    const std::string a = test::readBytes(dir.path("whole.gvr")), b = test::readBytes(dir.path("merged.gvr"));
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, b);

    // A merged asset is an ordinary one: gvr info reads it, and it names its bricks.
    const test::CommandResult info = test::runGvr("info --json '" + dir.path("merged.gvr") + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    EXPECT_EQ(nlohmann::json::parse(info.out)["fit"]["bricks"]["count"], 3);
}

TEST(CliBricks, BadBrickRequestsAndMergesGiveOneLineAndNoOutput) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);  // 24 x 20 x 16 voxels: 3 x 3 x 2 leaves
    const std::string fit = "fit -q '" + grid + "' --gaussians 60 --iterations 5 ";
    ASSERT_EQ(test::runGvr(fit + "--brick 0 --of 2 -o '" + dir.path("p0.gvr") + "'", dir).exitCode, 0);
    ASSERT_EQ(test::runGvr(fit + "-o '" + dir.path("plain.gvr") + "'", dir).exitCode, 0);
    const struct {
        std::string arguments, message;
    } cases[] = {
        {fit + "--bricks 64", "--bricks: 64 bricks"},
        {fit + "--brick 2 --of 2", "--brick: 2 is not below --of 2"},
        {fit + "--brick 0", "--brick requires --of"},
        {fit + "--bricks 2 --log '" + dir.path("x.csv") + "'", "excludes"},
        {"merge '" + dir.path("p0.gvr") + "'", "bricks 1 of 2 are missing"},
        {"merge '" + dir.path("p0.gvr") + "' '" + dir.path("p0.gvr") + "'", "repeats brick 0"},
        {"merge '" + dir.path("plain.gvr") + "'", "is not a brick part"},
        {"merge '" + dir.path("nothing.gvr") + "'", "nothing.gvr"},
    };
    for (const auto& c : cases) {
        const test::CommandResult run = test::runGvr(c.arguments + " -o '" + dir.path("out.gvr") + "'", dir);
        EXPECT_EQ(run.exitCode, 2) << c.arguments;
        EXPECT_EQ(test::lineCount(run.err), 1u) << c.arguments << "\n" << run.err;
        EXPECT_NE(run.err.find(c.message), std::string::npos) << c.arguments << "\n" << run.err;
        EXPECT_FALSE(std::filesystem::exists(dir.path("out.gvr"))) << c.arguments;
    }
}

TEST(CliBricks, AFailingBrickIsNamedAndNothingIsWritten) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    // A test hook, not a flag of gvr's: the child process inherits it.
    const test::ScopedEnvironment failBrick("GVR_TEST_FAIL_BRICK", "1");
    const test::CommandResult run = test::runGvr(
        "fit -q '" + grid + "' --gaussians 60 --iterations 5 --bricks 2 -o '" + dir.path("out.gvr") + "'", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.err.find("brick 1 (rank 0)"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("out.gvr")));
}

}  // namespace
}  // namespace gvr
