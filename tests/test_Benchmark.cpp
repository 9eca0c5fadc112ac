// The benchmark as a library call: rows reach the callback and the table, a merge
// of the folder is the same table, and bad options are refused before any work.

#include "bench/Benchmark.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace gvr;

namespace {

std::string writeQuickManifest(const test::TempDir& dir, const std::string& grid) {
    const std::string path = dir.path("bench.json");
    std::ofstream(path) << R"({
  "methods": ["vdb-half", "down2"],
  "render": {"size": "24x24", "views": 1},
  "volumes": [{"name": "blobs", "input": ")" +
                               grid + R"("}]
})";
    return path;
}

BenchOptions optionsFor(const test::TempDir& dir, const std::string& folder) {
    BenchOptions options;
    options.manifest = writeQuickManifest(dir, test::smallGrid(dir));
    options.folder = dir.path(folder);
    options.executable = GVR_EXECUTABLE;
    return options;
}

TEST(Benchmark, RunsEachMethodOnceAndReportsEveryRow) {
    test::TempDir dir;
    BenchOptions options = optionsFor(dir, "results");
    std::vector<std::string> seen;
    options.onRow = [&](const BenchRow& row, std::size_t done, std::size_t pending) {
        seen.push_back(row.get("method"));
        EXPECT_EQ(done, seen.size());
        EXPECT_EQ(pending, 2u);
    };
    const BenchSummary summary = runBenchmark(options);
    EXPECT_EQ(seen, (std::vector<std::string>{"vdb-half", "down2"}));
    ASSERT_EQ(summary.rows.size(), 2u);
    EXPECT_EQ(summary.failed, 0u) << summary.rows[0].get("message") << summary.rows[1].get("message");
    EXPECT_GT(summary.rows[1].number("psnr").value_or(0.0), 10.0);
    EXPECT_TRUE(std::filesystem::exists(summary.folder + "/report.md"));

    // Nothing left to run on resume; a merge of the one folder is the same table.
    options.resume = true;
    options.onRow = [](const BenchRow&, std::size_t, std::size_t) { ADD_FAILURE() << "nothing should run again"; };
    EXPECT_EQ(runBenchmark(options).rows.size(), 2u);
    // The same manifest elsewhere resumes it; another may not, since its rows would mix with these.
    BenchOptions moved = options;
    moved.manifest = dir.path("moved.json");
    std::filesystem::copy_file(options.manifest, moved.manifest);
    EXPECT_EQ(runBenchmark(moved).rows.size(), 2u);
    BenchOptions other = options;
    other.manifest = dir.path("other.json");
    std::ofstream(other.manifest) << test::readBytes(options.manifest) << "\n";
    try {
        runBenchmark(other);
        ADD_FAILURE() << "another manifest resumed the folder";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("holds the results of"), std::string::npos) << error.what();
    }
    const BenchSummary merged = mergeBenchResults({summary.folder}, dir.path("merged"));
    ASSERT_EQ(merged.rows.size(), 2u);
    EXPECT_EQ(merged.rows[1].get("psnr"), summary.rows[1].get("psnr"));
    EXPECT_EQ(merged.duplicates, 0u);
}

TEST(Benchmark, RefusesBadOptionsBeforeAnyWork) {
    test::TempDir dir;
    BenchOptions options = optionsFor(dir, "results");
    options.executable = dir.path("no-gvr");
    EXPECT_THROW(runBenchmark(options), InputError);
    options = optionsFor(dir, "results");
    options.shard = 2;
    options.shards = 2;
    EXPECT_THROW(runBenchmark(options), InputError);
    options = optionsFor(dir, "results");
    options.retryFailed = true;
    EXPECT_THROW(runBenchmark(options), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.path("results")));
}

}  // namespace

// Shards of two manifests once merged into one report of two benchmarks.
TEST(Benchmark, MergeRefusesShardsOfDifferentManifests) {
    test::TempDir dir;
    std::ofstream(dir.path("a.json")) << R"({"volumes": [{"input": "a.nii"}]})";
    std::ofstream(dir.path("b.json")) << R"({"volumes": [{"input": "b.nii"}]})";
    for (const char* shard : {"a", "b"}) {
        ResultsTable table(dir.path(std::string("shard-") + shard), dir.path(std::string(shard) + ".json"), false);
    }
    const std::string message = test::errorMessageOf<InputError>([&] {
        mergeBenchResults({dir.path("shard-a"), dir.path("shard-b")}, dir.path("merged"));
    });
    EXPECT_NE(message.find("shard-b: holds the results of another manifest (" + dir.path("b.json") + ")"),
              std::string::npos)
        << message;
    EXPECT_FALSE(std::filesystem::exists(dir.path("merged")));
}
