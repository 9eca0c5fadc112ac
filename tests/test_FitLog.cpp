#include "cli/FitLog.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <limits>

namespace gvr {
namespace {

FitProgress evaluated(std::size_t iteration, double psnr) {
    FitProgress p;
    p.iteration = iteration;
    p.seconds = 2.0;
    p.heldOutEvaluated = true;
    p.heldOutPsnr = psnr;
    p.gaussians = 50;
    return p;
}

TEST(FitLog, KeepsOneRowPerHeldOutEvaluationOnceFinished) {
    test::TempDir dir;
    const std::string path = dir.path("fit.csv");
    {
        FitLog log(path, 1.5);
        log.record(evaluated(10, 31.25));
        log.record(FitProgress{});  // no held-out evaluation: no row
        log.record(evaluated(20, std::numeric_limits<double>::infinity()));
        log.finish();
    }
    const std::string csv = test::readBytes(path);
    EXPECT_EQ(csv.rfind("iteration,seconds,loss,psnr_db,gaussians,peak_rss_mib,gradient_share\n10,3.5,0,31.25,50,", 0),
              0u)
        << csv;
    EXPECT_NE(csv.find("\n20,3.5,0,inf,50,"), std::string::npos) << csv;
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
}

TEST(FitLog, AFitThatNeverFinishesLeavesNoLog) {
    test::TempDir dir;
    const std::string path = dir.path("fit.csv");
    {
        FitLog log(path, 0.0);
        log.record(evaluated(10, 30.0));
        EXPECT_TRUE(std::filesystem::exists(path));  // watchable while the fit runs
    }
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(FitLog, ASignalRemovesAnUnfinishedLog) {
    // SIGTERM during a fit left a partial log with exit 143.
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    test::DeathTestDir dir;
    const std::string path = dir.path("fit.csv");
    const auto logThenGetKilled = [&] {
        removeTemporariesOnSignals();
        FitLog log(path, 0.0);
        log.record(evaluated(10, 31.25));
        std::raise(SIGTERM);
    };
    EXPECT_EXIT(logThenGetKilled(), ::testing::KilledBySignal(SIGTERM), "");
    EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(FitLog, NoPathWritesNothingAndAnUnwritablePathIsNamed) {
    FitLog none("", 0.0);
    none.record(evaluated(1, 30.0));
    none.finish();
    test::TempDir dir;
    const std::string bad = dir.path("missing/fit.csv");
    EXPECT_NE(test::errorMessageOf<InputError>([&] { FitLog log(bad, 0.0); }).find(bad), std::string::npos);
}

}  // namespace
}  // namespace gvr
