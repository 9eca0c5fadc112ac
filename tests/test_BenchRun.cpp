// The runner of one volume's benchmark rows, against a stand-in for gvr: rows the
// table holds are not run again, and a failed first step fails every pending row
// with that step's message. Real runs are in test_Benchmark.cpp.

#include "bench/BenchRun.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gvr {
namespace {

/// A "gvr" that notes its arguments in @a calls, prints @a error and exits with @a code.
std::string fakeGvr(const test::TempDir& dir, const std::string& error, int code) {
    const std::string path = dir.path("fake-gvr");
    test::writeBytes(path, "#!/bin/sh\necho \"$*\" >> '" + dir.path("calls") + "'\n" +
                               (error.empty() ? "" : "echo '" + error + "' >&2\n") + "exit " + std::to_string(code) +
                               "\n");
    std::filesystem::permissions(path, std::filesystem::perms::owner_all);
    return path;
}

BenchManifest blobsManifest(const test::TempDir& dir) {
    BenchManifest manifest;
    manifest.path = dir.path("bench.json");
    BenchVolume volume;
    volume.name = "blobs";
    volume.input = dir.path("scan.nii");
    manifest.volumes = {volume};
    manifest.methods = {"vdb-half", "gvr"};
    return manifest;
}

BenchRow rowOf(const std::string& method, const std::string& ratio) {
    BenchRow row;
    row.set("volume", "blobs");
    row.set("ratio", ratio);
    row.set("method", method);
    row.set("status", "ok");
    return row;
}

const std::vector<BenchUnit> kUnits = {BenchUnit{0, std::nullopt, {"vdb-half"}}, BenchUnit{0, 10.0, {"gvr"}}};

TEST(BenchRun, AFailedIngestFailsEveryPendingRowWithItsMessage) {
    test::TempDir dir;
    const BenchManifest manifest = blobsManifest(dir);
    ResultsTable table(dir.path("results"), manifest.path, /*resume=*/false);
    std::vector<std::string> reported;
    BenchContext context;
    context.manifest = &manifest;
    context.folder = dir.path("results");
    context.executable = fakeGvr(dir, "gvr: error: scan.nii: truncated after 100 bytes", 2);
    context.table = &table;
    context.onRow = [&](const BenchRow& row) { reported.push_back(row.key()); };
    runVolumeUnits(context, kUnits);

    EXPECT_EQ(reported, (std::vector<std::string>{"blobs||vdb-half", "blobs|10|gvr"}));
    const std::vector<BenchRow> rows = table.rows();
    ASSERT_EQ(rows.size(), 2u);
    for (const BenchRow& row : rows) {
        EXPECT_EQ(row.get("status"), "failed") << row.key();
        // gvr's own prefix is dropped; the step is named instead.
        EXPECT_EQ(row.get("message"), "ingest failed (exit 2): scan.nii: truncated after 100 bytes") << row.key();
    }
    EXPECT_EQ(readResultsCsv(table.csvPath()).size(), 2u);  // on disk as each row ends
    // One ingest for the volume, not one per row.
    EXPECT_EQ(test::readBytes(dir.path("calls")),
              "ingest " + dir.path("scan.nii") + " -o " + dir.path("results/work/blobs/source.vdb") + " -q --json\n");
}

TEST(BenchRun, AStepThatSaysNothingPointsAtItsLog) {
    test::TempDir dir;
    const BenchManifest manifest = blobsManifest(dir);
    ResultsTable table(dir.path("results"), manifest.path, /*resume=*/false);
    BenchContext context;
    context.manifest = &manifest;
    context.folder = dir.path("results");
    context.executable = fakeGvr(dir, "", 1);
    context.table = &table;
    runVolumeUnits(context, {BenchUnit{0, std::nullopt, {"vdb-half"}}});
    ASSERT_EQ(table.rows().size(), 1u);
    EXPECT_EQ(table.rows()[0].get("message"), "ingest failed (exit 1): no message; see work/blobs/log.txt");
}

TEST(BenchRun, RowsTheTableHoldsAreNotRunAgain) {
    test::TempDir dir;
    const BenchManifest manifest = blobsManifest(dir);
    ResultsTable table(dir.path("results"), manifest.path, /*resume=*/false);
    table.append(rowOf("vdb-half", ""));
    table.append(rowOf("gvr", "10"));
    std::size_t reported = 0;
    BenchContext context;
    context.manifest = &manifest;
    context.folder = dir.path("results");
    context.executable = fakeGvr(dir, "gvr: error: must not run", 2);
    context.table = &table;
    context.onRow = [&](const BenchRow&) { ++reported; };
    runVolumeUnits(context, kUnits);
    runVolumeUnits(context, {});
    EXPECT_EQ(reported, 0u);
    EXPECT_EQ(table.rows().size(), 2u);
    EXPECT_FALSE(std::filesystem::exists(dir.path("calls"))) << "gvr was run";
    EXPECT_FALSE(std::filesystem::exists(dir.path("results/work"))) << "the volume was prepared for nothing";
}

TEST(BenchRun, OnlyTheMissingRowIsRun) {
    test::TempDir dir;
    const BenchManifest manifest = blobsManifest(dir);
    ResultsTable table(dir.path("results"), manifest.path, /*resume=*/false);
    table.append(rowOf("vdb-half", ""));
    std::vector<std::string> reported;
    BenchContext context;
    context.manifest = &manifest;
    context.folder = dir.path("results");
    context.executable = fakeGvr(dir, "gvr: error: scan.nii: truncated", 2);
    context.table = &table;
    context.onRow = [&](const BenchRow& row) { reported.push_back(row.key()); };
    runVolumeUnits(context, kUnits);
    EXPECT_EQ(reported, (std::vector<std::string>{"blobs|10|gvr"}));
    ASSERT_EQ(table.rows().size(), 2u);
    EXPECT_EQ(table.rows()[0].get("status"), "ok");
    EXPECT_EQ(table.rows()[1].get("status"), "failed");
}

}  // namespace
}  // namespace gvr
