// gvr bench end to end on a tiny manifest: every method gives a row, a missing
// volume gives failed rows, a kill -9 followed by --resume ends with the same
// table as an uninterrupted run, and shards merge into the whole; external codecs
// match gvr's bytes, and a faulty one fails only its own row.

#include "bench/BenchTable.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <map>
#include <thread>

using namespace gvr;
using test::runGvr;

namespace {

/// Reproducible: fits by iteration count, so quality and sizes repeat exactly.
std::string writeReproducibleManifest(const test::TempDir& dir, const std::string& grid) {
    const std::string path = dir.path("bench.json");
    std::ofstream(path) << R"({
  "ratios": [8],
  "methods": ["gvr", "A4", "zfp-accuracy", "zfp-rate", "vdb-blosc", "vdb-half", "down2"],
  "fit": {"iterations": 40, "args": ["--batch", "2048", "--threads", "1"]},
  "render": {"size": "32x32", "views": 2},
  "volumes": [{"name": "blobs", "input": ")" +
                               grid + R"("}, {"name": "lost", "input": "no/such.nii.gz"}]
})";
    return path;
}

/// What must not depend on timing, interruption or sharding.
std::vector<std::string> outcome(const std::string& resultsCsv) {
    std::vector<std::string> rows;
    for (const BenchRow& row : readResultsCsv(resultsCsv)) {
        std::string text;
        for (const char* column : {"volume", "ratio", "method", "status", "bytes", "psnr", "fg_psnr", "ssim", "ms_ssim",
                                   "render_psnr", "render_ssim", "detail"}) {
            text += row.get(column) + "|";
        }
        rows.push_back(text);
    }
    std::sort(rows.begin(), rows.end());
    return rows;
}

std::size_t rowsIn(const std::string& resultsCsv) {
    std::ifstream in(resultsCsv);
    return std::size_t(std::count(std::istreambuf_iterator<char>(in), {}, '\n'));
}

pid_t startBench(const std::string& manifest, const std::string& out, const std::string& errors = "/dev/null") {
    const pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        freopen(errors.c_str(), "w", stderr);
        execl(GVR_EXECUTABLE, GVR_EXECUTABLE, "bench", manifest.c_str(), "-o", out.c_str(), "-q", (char*)nullptr);
        _exit(127);
    }
    return pid;
}

class CliBench : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir = new test::TempDir;
        manifest = writeReproducibleManifest(*dir, test::smallGrid(*dir));
        complete = runGvr("bench '" + manifest + "' -o '" + dir->path("complete") + "' --json", *dir);
    }
    static void TearDownTestSuite() { delete dir; }

    static test::TempDir* dir;
    static std::string manifest;
    static test::CommandResult complete;
};

test::TempDir* CliBench::dir = nullptr;
std::string CliBench::manifest;
test::CommandResult CliBench::complete;

}  // namespace

TEST_F(CliBench, EveryMethodGivesARowAndAMissingVolumeFailsWithoutStoppingTheRun) {
    ASSERT_EQ(complete.exitCode, 0) << complete.err;
    const std::vector<BenchRow> rows = readResultsCsv(dir->path("complete/results.csv"));
    ASSERT_EQ(rows.size(), 14u);  // 7 methods x 2 volumes
    for (const BenchRow& row : rows) {
        SCOPED_TRACE(row.key() + ": " + row.get("message"));
        if (row.get("volume") == "lost") {
            EXPECT_EQ(row.get("status"), "failed");
            EXPECT_NE(row.get("message").find("no/such.nii.gz"), std::string::npos);
            continue;
        }
        ASSERT_EQ(row.get("status"), "ok");
        EXPECT_GT(*row.number("bytes"), 0);
        EXPECT_GT(*row.number("psnr"), 15.0);
        EXPECT_GT(*row.number("render_psnr"), 15.0);
        EXPECT_GT(*row.number("render_fps"), 0);
        EXPECT_EQ(row.list("views").size(), 2u);
        for (const std::string& view : row.list("views"))
            EXPECT_TRUE(std::filesystem::exists(dir->path("complete/" + view)));
    }
    const auto find = [&](const std::string& method) {
        return *std::find_if(rows.begin(), rows.end(),
                             [&](const BenchRow& r) { return r.key() == "blobs|8|" + method; });
    };
    EXPECT_FALSE(find("gvr").get("fit_log").empty());
    // ZFP's tolerance search matched gvr's asset size within 5 %.
    EXPECT_NEAR(*find("zfp-accuracy").number("bytes") / *find("gvr").number("bytes"), 1.0, 0.05);
    const BenchRow lossless =
        *std::find_if(rows.begin(), rows.end(), [](const BenchRow& r) { return r.get("method") == "vdb-blosc"; });
    EXPECT_EQ(lossless.get("psnr"), "inf");
    EXPECT_TRUE(lossless.get("ratio").empty());

    const std::string report = test::readBytes(dir->path("complete/report.md"));
    for (const char* part : {"Table 1", "Table 2", "Table 3", "Verdicts", "Failed runs", "no/such.nii.gz"}) {
        EXPECT_NE(report.find(part), std::string::npos) << part;
    }
    for (const char* plot : {"blobs_r8_psnr_vs_time.png", "blobs_rate_distortion.png", "blobs_r8_contact_sheet.png"}) {
        EXPECT_TRUE(std::filesystem::exists(dir->path(std::string("complete/plots/") + plot))) << plot;
    }
}

TEST_F(CliBench, KillNineThenResumeGivesTheSameTable) {
    ASSERT_EQ(complete.exitCode, 0) << complete.err;
    const std::string out = dir->path("killed"), csv = out + "/results.csv";
    const pid_t pid = startBench(manifest, out);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (rowsIn(csv) < 4 && std::chrono::steady_clock::now() < deadline) {  // header + 3 rows
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    const std::size_t rowsAtKill = rowsIn(csv) - 1;
    ASSERT_GE(rowsAtKill, 3u);
    ASSERT_LT(rowsAtKill, 14u) << "the run ended before it could be killed";
    EXPECT_NE(runGvr("bench '" + manifest + "' -o '" + out + "' -q", *dir).exitCode, 0) << "needs --resume";
    const test::CommandResult resumed = runGvr("bench '" + manifest + "' -o '" + out + "' --resume -q", *dir);
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_EQ(outcome(csv), outcome(dir->path("complete/results.csv")));
}

// Ctrl-C once ended a bench without a word.
TEST_F(CliBench, CtrlCSaysHowToCarryOn) {
    const std::string out = dir->path("interrupted"), csv = out + "/results.csv", errors = dir->path("interrupted.err");
    const pid_t pid = startBench(manifest, out, errors);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (rowsIn(csv) < 2 && std::chrono::steady_clock::now() < deadline) {  // header + 1 row
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
    const std::string said = test::readBytes(errors);
    EXPECT_NE(said.find("gvr bench: stopped; the runs that ended are kept in " + csv + "; carry on with: gvr bench " +
                        manifest + " -o " + out + " --resume\n"),
              std::string::npos)
        << said;
}

TEST_F(CliBench, ShardsMergeIntoTheWhole) {
    ASSERT_EQ(complete.exitCode, 0) << complete.err;
    for (int s = 0; s < 2; ++s) {
        const std::string shard = std::to_string(s) + "/2";
        const test::CommandResult run = runGvr(
            "bench '" + manifest + "' -o '" + dir->path("shard" + std::to_string(s)) + "' --shard " + shard + " -q",
            *dir);
        ASSERT_EQ(run.exitCode, 0) << run.err;
        EXPECT_LT(readResultsCsv(dir->path("shard" + std::to_string(s) + "/results.csv")).size(), 14u);
    }
    const test::CommandResult merged = runGvr(
        "bench --merge '" + dir->path("shard0") + "' '" + dir->path("shard1") + "' -o '" + dir->path("merged") + "' -q",
        *dir);
    ASSERT_EQ(merged.exitCode, 0) << merged.err;
    EXPECT_EQ(outcome(dir->path("merged/results.csv")), outcome(dir->path("complete/results.csv")));
    for (const BenchRow& row : readResultsCsv(dir->path("merged/results.csv"))) {
        for (const std::string& view : row.list("views"))
            EXPECT_TRUE(std::filesystem::exists(dir->path("merged/" + view))) << view;
    }
}

TEST_F(CliBench, ConcurrentJobsGiveTheSameTable) {
    ASSERT_EQ(complete.exitCode, 0) << complete.err;
    const test::CommandResult run = runGvr("bench '" + manifest + "' -o '" + dir->path("jobs") + "' --jobs 2 -q", *dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(outcome(dir->path("jobs/results.csv")), outcome(dir->path("complete/results.csv")));
}

TEST_F(CliBench, BadFlagsAreRefused) {
    EXPECT_EQ(runGvr("bench '" + manifest + "' -o '" + dir->path("x") + "' --shard 2/2", *dir).exitCode, 2);
    EXPECT_EQ(runGvr("bench -o '" + dir->path("y") + "'", *dir).exitCode, 2);
    const test::CommandResult bad = runGvr("bench '" + dir->path("nope.json") + "' -o '" + dir->path("z") + "'", *dir);
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_EQ(test::lineCount(bad.err), 1u) << bad.err;
    EXPECT_NE(bad.err.find("nope.json"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir->path("z/results.csv")));
}

namespace {

/// Codecs over tests/fake_codec.py: one that works and one for each way of failing.
std::string writeCodecManifest(const test::TempDir& dir, const std::string& grid) {
    const std::string codec = "\"/usr/bin/python3\", \"" + std::string(GVR_TEST_DATA) + "/../fake_codec.py\"";
    // Only the hanging codec gets a short limit: the others must pass on a loaded machine.
    const auto spec = [&](const std::string& compressMode, const std::string& decompressMode,
                          const std::string& extra = "", const std::string& program = "") {
        const std::string timeout = compressMode == "hang" ? "2" : "120";
        const std::string head = program.empty() ? codec : "\"" + program + "\"";
        return R"({"compress": [)" + head + R"(, "c", ")" + compressMode +
               R"(", "{input}", "{nx}", "{ny}", "{nz}", "{param}", "{compressed}")" + extra + R"(],
                   "decompress": [)" +
               head + R"(, "d", ")" + decompressMode +
               R"(", "{compressed}", "{output}", "{nx}", "{ny}", "{nz}"],
                   "param": [1e-8, 10], "version": "fake 1.0", "timeout": )" +
               timeout + "}";
    };
    const std::string path = dir.path("codecs.json");
    std::ofstream(path) << R"({
  "ratios": [8],
  "methods": ["gvr", "good", "badph", "fails", "hangs", "empty", "short", "missing"],
  "fit": {"iterations": 20, "args": ["--batch", "2048", "--threads", "1"]},
  "render": {"size": "32x32", "views": 2},
  "codecs": {
    "good": )" + spec("quantise", "quantise") +
                               R"(,
    "badph": )" + spec("quantise", "quantise", R"(, "{level}")") +
                               R"(,
    "fails": )" + spec("fail", "quantise") +
                               R"(,
    "hangs": )" + spec("hang", "quantise") +
                               R"(,
    "empty": )" + spec("nothing", "quantise") +
                               R"(,
    "short": )" + spec("quantise", "short") +
                               R"(,
    "missing": )" + spec("quantise", "quantise", "", "no-such-codec") +
                               R"(
  },
  "volumes": [{"name": "blobs", "input": ")" +
                               grid + R"("}]
})";
    return path;
}

}  // namespace

TEST(CliBenchCodecs, ACodecMatchesGvrsBytesAndEveryFaultyCodecFailsOnlyItsOwnRow) {
    test::TempDir dir;
    const std::string manifest = writeCodecManifest(dir, test::smallGrid(dir));
    const test::CommandResult run = runGvr("bench '" + manifest + "' -o '" + dir.path("out") + "'", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.out.find("8 rows (5 failed, 1 skipped)"), std::string::npos) << run.out;
    EXPECT_NE(run.err.find("gvr: warning: codec missing: program 'no-such-codec' not found on PATH; its rows are "
                           "skipped\n"),
              std::string::npos)
        << run.err;

    std::map<std::string, BenchRow> rows;
    for (const BenchRow& row : readResultsCsv(dir.path("out/results.csv"))) rows[row.get("method")] = row;
    ASSERT_EQ(rows.size(), 8u);
    ASSERT_EQ(rows["gvr"].get("status"), "ok") << rows["gvr"].get("message");
    const BenchRow& good = rows["good"];
    ASSERT_EQ(good.get("status"), "ok") << good.get("message");
    EXPECT_NEAR(*good.number("bytes") / *rows["gvr"].number("bytes"), 1.0, 0.05) << "the search matches gvr's asset";
    for (const char* column : {"psnr", "fg_psnr", "ssim", "ms_ssim", "render_psnr", "compress_s", "decompress_s"}) {
        EXPECT_TRUE(good.number(column).has_value()) << column;
    }
    EXPECT_GT(*good.number("psnr"), 20.0);
    EXPECT_NE(good.get("detail").find("param "), std::string::npos);

    const std::map<std::string, std::string> expected = {{"badph", "unknown placeholder {level}"},
                                                         {"fails", "exit 3"},
                                                         {"hangs", "time limit of 2 s"},
                                                         {"empty", "wrote no file"},
                                                         {"short", "float32 voxels are"}};
    for (const auto& [method, message] : expected) {
        SCOPED_TRACE(method);
        EXPECT_EQ(rows[method].get("status"), "failed");
        EXPECT_NE(rows[method].get("message").find(method + ": "), std::string::npos) << rows[method].get("message");
        EXPECT_NE(rows[method].get("message").find(message), std::string::npos) << rows[method].get("message");
        EXPECT_NE(run.err.find("blobs, " + method + " (target 8:1): FAILED: "), std::string::npos) << "names the row";
        for (const char* column : {"bytes", "psnr", "render_psnr"}) EXPECT_EQ(rows[method].get(column), "") << column;
    }
    EXPECT_EQ(rows["missing"].get("status"), "skipped");

    const std::string report = test::readBytes(dir.path("out/report.md"));
    for (const char* part : {"## Codecs", "fake 1.0", "fake_codec.py c quantise {input} {nx} {ny} {nz} {param}",
                             "## Skipped runs", "'no-such-codec' not found", "| good |"}) {
        EXPECT_NE(report.find(part), std::string::npos) << part;
    }
    // A merged folder keeps the codecs' record, so its report still names commands and versions.
    const test::CommandResult merged =
        runGvr("bench --merge '" + dir.path("out") + "' -o '" + dir.path("merged") + "' -q", dir);
    ASSERT_EQ(merged.exitCode, 0) << merged.err;
    EXPECT_NE(test::readBytes(dir.path("merged/codecs.json")).find("\"fake 1.0\""), std::string::npos);
    EXPECT_NE(test::readBytes(dir.path("merged/report.md")).find("fake 1.0"), std::string::npos);
}

TEST(CliBenchBound, GvrWithABoundFitsTheRatioAndReportsItsMaximumError) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = dir.path("bound.json");
    std::ofstream(path) << R"({
  "ratios": [10],
  "methods": ["gvr+bound", "down2"],
  "fit": {"iterations": 5},
  "render": {"size": "32x32", "views": 1},
  "volumes": [{"name": "ch2", "input": ")" +
                               test::sharedData("mri-colin27-aal/ch2.nii.gz") + R"("}]
})";
    const test::CommandResult run = runGvr("bench '" + path + "' -o '" + dir.path("out") + "'", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    std::map<std::string, BenchRow> rows;
    for (const BenchRow& row : readResultsCsv(dir.path("out/results.csv"))) rows[row.get("method")] = row;
    const BenchRow& bounded = rows["gvr+bound"];
    ASSERT_EQ(bounded.get("status"), "ok") << bounded.get("message");
    EXPECT_GE(*bounded.number("ratio_raw"), 10.0);
    const std::string detail = bounded.get("detail");
    const std::size_t within = detail.find("every voxel within ");
    ASSERT_NE(within, std::string::npos) << detail;
    EXPECT_LE(*bounded.number("max_error"), std::stod(detail.substr(within + 19))) << detail;
    EXPECT_GT(*rows["down2"].number("max_error"), 0.0);  // every method reports it
}
