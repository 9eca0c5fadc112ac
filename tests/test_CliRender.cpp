// gvr render as a user meets it: a CT frame against a stored image, turntables
// and their statistics, both renderers on assets, and bad input.

#include "pipeline/Fitter.h"
#include "pipeline/QualityMetrics.h"
#include "tests/TestHelpers.h"
#include "workflow/ComparisonInput.h"

#include <nlohmann/json.hpp>

namespace gvr {
namespace {

using test::runGvr;

double pngPsnr(const std::string& a, const std::string& b) {
    const ComparisonInput x = loadComparisonInput(a, {}), y = loadComparisonInput(b, {});
    EXPECT_EQ(x.volume.dims, y.volume.dims);
    return psnrFromMse(meanSquaredError(x.volume, y.volume), 1.0);
}

TEST(CliRender, CtFrameMatchesTheStoredImage) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string grid = dir.path("ct.vdb"), frame = dir.path("ct.png");
    ASSERT_EQ(
        runGvr("ingest -q '" + test::sharedData("ct-head-visible-human-png") + "' -o '" + grid + "'", dir).exitCode, 0);
    // Made once with this command (view stacks were the only ones then) and checked
    // by eye: head above the shoulders and the table.
    const test::CommandResult run = runGvr(
        "render -q '" + grid + "' -o '" + frame + "' --size 160x160 --azimuth 30 --elevation 15 --stacks view", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_GE(pngPsnr(frame, std::string(GVR_TEST_DATA) + "/ct_head_160.png"), 40.0);
}

TEST(CliRender, AnOrbitBuildsOneStackAnAxis) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    // Azimuth 30 + 45 f at elevation 15 looks along y, x, x, y, y, x, x, y.
    const test::CommandResult run =
        runGvr("render -q '" + grid + "' -o '" + dir.path("turn.png") + "' --size 48x48 --orbit 8 --json", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    const nlohmann::json& frames = report["frames"];
    ASSERT_EQ(frames.size(), 8u);
    for (int f = 0; f < 8; ++f) EXPECT_EQ(frames[f]["reused"], f != 0 && f != 1) << f;
    // --stacks auto gives an orbit axis stacks, and the report says so.
    EXPECT_EQ(report["settings"]["stacks"], "axes");
    EXPECT_EQ(report["settings"]["supersample"], 1.5);
}

TEST(CliRender, OrbitReusesTheStackAndWritesStatistics) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const test::CommandResult run =
        runGvr("render -q '" + grid + "' -o '" + dir.path("turn.png") +
                   "' --size 48x48 --orbit 8 --stacks view --reuse-angle 50 --stats '" + dir.path("stats.json") + "'",
               dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json stats = nlohmann::json::parse(test::readBytes(dir.path("stats.json")));
    ASSERT_EQ(stats["frames"].size(), 8u);
    for (int f = 0; f < 8; ++f) {
        const nlohmann::json& frame = stats["frames"][f];
        EXPECT_TRUE(std::filesystem::exists(dir.path("turn_000" + std::to_string(f) + ".png")));
        EXPECT_EQ(frame["index"], f);
        EXPECT_EQ(frame["reused"], f % 2 == 1) << f;  // 45 degree steps, a 50 degree cone
        for (const char* key : {"build_ms", "composite_ms", "warp_ms", "total_ms", "gaussians_touched"}) {
            EXPECT_TRUE(frame.contains(key)) << key;
        }
    }
    for (const char* phase : {"read", "classify", "total"})
        EXPECT_TRUE(stats["setup_seconds"].contains(phase)) << phase;
    // The wait for the first frame counts its set-up and its own time.
    const double firstFrameMs = stats["first_frame_ms"].get<double>();
    EXPECT_GE(firstFrameMs, 1000.0 * stats["setup_seconds"]["total"].get<double>());
    EXPECT_GE(firstFrameMs, stats["frames"][0]["total_ms"].get<double>());
}

TEST(CliRender, AssetsRenderWithBothRenderersAndAgree) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir), asset = dir.path("small.asset");
    ASSERT_EQ(runGvr("fit -q '" + grid + "' -o '" + asset + "' --gaussians 150 --iterations 80", dir).exitCode, 0);
    const std::string common = "render -q '" + asset + "' --size 64x64 --tf mri ";
    const test::CommandResult shearWarp = runGvr(common + "-o '" + dir.path("sw.png") + "' --json", dir);
    ASSERT_EQ(shearWarp.exitCode, 0) << shearWarp.err;
    const nlohmann::json report = nlohmann::json::parse(shearWarp.out);
    EXPECT_GT(report["frames"][0]["gaussians_touched"].get<int>(), 100);
    EXPECT_EQ(report["settings"]["stacks"], "view") << "--stacks auto: a still gets a stack across its view";
    ASSERT_EQ(runGvr(common + "-o '" + dir.path("rm.exr") + "' --renderer raymarch", dir).exitCode, 0);
    ASSERT_EQ(runGvr(common + "-o '" + dir.path("rm.png") + "' --renderer raymarch", dir).exitCode, 0);
    EXPECT_GE(pngPsnr(dir.path("sw.png"), dir.path("rm.png")), 30.0);
    EXPECT_GT(std::filesystem::file_size(dir.path("rm.exr")), 0u);
}

TEST(CliRender, ClassifyTakesPointsOrSegmentsAndTheReportSaysWhich) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string common = "render -q '" + grid + "' --size 32x32 --tf mri --json ";
    const test::CommandResult points = runGvr(common + "-o '" + dir.path("points.png") + "'", dir);
    ASSERT_EQ(points.exitCode, 0) << points.err;
    EXPECT_EQ(nlohmann::json::parse(points.out)["settings"]["classify"], "points");
    const test::CommandResult segments =
        runGvr(common + "--classify segments -o '" + dir.path("segments.png") + "'", dir);
    ASSERT_EQ(segments.exitCode, 0) << segments.err;
    EXPECT_EQ(nlohmann::json::parse(segments.out)["settings"]["classify"], "segments");
    EXPECT_GE(pngPsnr(dir.path("segments.png"), dir.path("points.png")), 30.0);
    const test::CommandResult wrong = runGvr(common + "--classify lines -o '" + dir.path("wrong.png") + "'", dir);
    EXPECT_NE(wrong.exitCode, 0);
    EXPECT_NE(wrong.err.find("--classify"), std::string::npos) << wrong.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("wrong.png")));
}

TEST(CliRender, PresetNamesIgnoreCase) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    for (const char* name : {"mri", "MRI", "Mri"}) {
        const test::CommandResult run = runGvr(
            "render -q '" + grid + "' --size 32x32 --tf " + name + " -o '" + dir.path(std::string(name) + ".png") + "'",
            dir);
        ASSERT_EQ(run.exitCode, 0) << name << ": " << run.err;
    }
    EXPECT_EQ(test::readBytes(dir.path("mri.png")), test::readBytes(dir.path("MRI.png")));
}

TEST(CliRender, AFullDiskLeavesNoFrameAndFails) {
    // ulimit -f stands in for a full disk: OpenImageIO's PNG writer once left a cut
    // file and gvr said "wrote".
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const test::CommandResult run = test::runGvr("--version >/dev/null; ulimit -f 1; '" GVR_EXECUTABLE "' render '" +
                                                     grid + "' --size 512x512 --orbit 2 -o '" + dir.path("f.png") + "'",
                                                 dir);
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_NE(run.err.find("cannot write the image"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("f_0000.png")));
    EXPECT_FALSE(std::filesystem::exists(dir.path("f_0001.png")));
}

TEST(CliRender, BadInputLeavesNoImage) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    std::filesystem::create_directory(dir.path("out"));
    test::writeBytes(dir.path("bad.json"), R"({"points": [[0, 2, 0, 0, 0]]})");
    for (const std::string& flags :
         {std::string("--size 0x10"), std::string("--size big"), std::string("--tf bone"),
          "--tf '" + dir.path("bad.json") + "'", std::string("--reuse-angle 90"), std::string("--stacks diagonal"),
          std::string("--stacks 1"), std::string("--slice-spacing 0"), std::string("--slice-spacing 1e-9"),
          std::string("--renderer raymarch --step 1e-9"), std::string("--azimuth nan")}) {
        const test::CommandResult run =
            runGvr("render '" + grid + "' -o '" + dir.path("out/x.png") + "' " + flags, dir);
        EXPECT_EQ(run.exitCode, 2) << flags << "\n" << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << flags << "\n" << run.err;
    }
    const test::CommandResult jpeg = runGvr("render '" + grid + "' -o '" + dir.path("out/x.jpg") + "'", dir);
    EXPECT_EQ(jpeg.exitCode, 2);
    EXPECT_NE(jpeg.err.find(".png"), std::string::npos) << jpeg.err;
    EXPECT_TRUE(std::filesystem::is_empty(dir.path("out")));
}

}  // namespace
}  // namespace gvr
