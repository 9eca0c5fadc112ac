// Benchmark results: rows survive a round trip through results.csv, and a row torn
// by a kill is dropped on resume.

#include "bench/BenchTable.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

using namespace gvr;

namespace {

BenchRow sampleRow(const std::string& method) {
    BenchRow row;
    row.set("volume", "ct head");
    row.set("ratio", "10");
    row.set("method", method);
    row.set("status", "failed");
    row.set("message", "fit: \"odd\", with commas\nand a newline");
    row.set("psnr", INFINITY);
    row.set("ssim", 0.987654321);
    row.set("bytes", 123456.0);
    row.setList("views", {"runs/a/view_0000.png", "runs/a/view_0001.png"});
    return row;
}

}  // namespace

TEST(BenchTable, RowsRoundTripThroughCsvAndJson) {
    test::TempDir dir;
    {
        ResultsTable table(dir.path("out"), "m.json", /*resume=*/false);
        table.append(sampleRow("gvr"));
        table.append(sampleRow("A1"));
    }
    const std::vector<BenchRow> rows = readResultsCsv(dir.path("out/results.csv"));
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].get("message"), "fit: \"odd\", with commas and a newline");
    EXPECT_EQ(rows[1].key(), "ct head|10|A1");
    EXPECT_EQ(rows[0].number("psnr"), std::optional<double>(INFINITY));
    EXPECT_NEAR(*rows[0].number("ssim"), 0.987654321, 1e-10);
    EXPECT_EQ(rows[0].list("views").size(), 2u);

    std::ifstream in(dir.path("out/results.json"));
    const nlohmann::json json = nlohmann::json::parse(in);
    ASSERT_EQ(json["rows"].size(), 2u);
    // JSON has no infinity: null, and the column named as infinite.
    EXPECT_TRUE(json["rows"][0]["psnr"].is_null());
    EXPECT_EQ(json["rows"][0]["infinite"], nlohmann::json::array({"psnr"}));
    EXPECT_EQ(json["rows"][1]["infinite"], nlohmann::json::array({"psnr"}));
    EXPECT_EQ(json["rows"][0]["bytes"], 123456.0);
    EXPECT_TRUE(json["rows"][0]["fg_psnr"].is_null());
    EXPECT_EQ(json["rows"][0]["views"][1], "runs/a/view_0001.png");
}

TEST(BenchTable, ResumeDropsATornLastRowAndRefusesWithoutResume) {
    test::TempDir dir;
    {
        ResultsTable table(dir.path("out"), "m.json", false);
        table.append(sampleRow("gvr"));
    }
    {  // a kill in the middle of writing the second row
        std::ofstream out(dir.path("out/results.csv"), std::ios::app);
        out << "ct head,10,A1,ok,,12";
    }
    EXPECT_THROW(ResultsTable(dir.path("out"), "m.json", false), InputError);
    ResultsTable resumed(dir.path("out"), "m.json", /*resume=*/true);
    ASSERT_EQ(resumed.rows().size(), 1u);
    EXPECT_TRUE(resumed.find("ct head|10|gvr"));
    EXPECT_FALSE(resumed.find("ct head|10|A1"));
    resumed.append(sampleRow("A1"));
    EXPECT_EQ(readResultsCsv(dir.path("out/results.csv")).size(), 2u);
}

TEST(BenchTable, RetryFailedDropsOnlyFailedRows) {
    test::TempDir dir;
    {
        ResultsTable table(dir.path("out"), "m.json", false);
        table.append(sampleRow("gvr"));  // failed
        BenchRow ok = sampleRow("A1");
        ok.set("status", "ok");
        table.append(ok);
    }
    ResultsTable retried(dir.path("out"), "m.json", /*resume=*/true, /*retryFailed=*/true);
    EXPECT_FALSE(retried.find("ct head|10|gvr"));
    EXPECT_TRUE(retried.find("ct head|10|A1"));
    EXPECT_EQ(readResultsCsv(dir.path("out/results.csv")).size(), 1u);
}

TEST(BenchTable, ForeignCsvIsRefused) {
    test::TempDir dir;
    std::ofstream(dir.path("results.csv")) << "a,b,c\n1,2,3\n";
    EXPECT_THROW(readResultsCsv(dir.path("results.csv")), InputError);
}

namespace {

std::string tableError(const std::string& folder, const std::vector<std::string>& knownMethods = {}) {
    return test::errorMessageOf<InputError>(
        [&] { ResultsTable(folder, "m.json", /*resume=*/true, /*retryFailed=*/false, knownMethods); });
}

/// A results folder of one measured row, its table closed.
std::string folderOfOneRow(const test::TempDir& dir, const std::string& name) {
    ResultsTable table(dir.path(name), "m.json", false);
    BenchRow ok = sampleRow("gvr");
    ok.set("status", "ok");
    table.append(ok);
    return dir.path(name);
}

void appendLine(const std::string& folder, const std::string& line) {
    std::ofstream(folder + "/results.csv", std::ios::app) << line << "\n";
}

std::string csvLineOf(const BenchRow& row) {
    std::string line;
    for (const std::string& column : benchColumns()) line += (line.empty() ? "" : ",") + row.get(column);
    return line;
}

}  // namespace

// A results folder is input: what no run writes is refused in one line on resume.
TEST(BenchTable, ResumeRefusesWhatTheBenchDidNotWrite) {
    test::TempDir dir;
    BenchRow row = sampleRow("A1");
    row.set("message", "");
    row.set("status", "running");
    const std::string running = folderOfOneRow(dir, "running");
    appendLine(running, csvLineOf(row));
    EXPECT_NE(tableError(running).find("row 2 (ct head|10|A1) has status 'running', which the bench never writes"),
              std::string::npos);

    row.set("status", "ok");
    row.set("bytes", "many");
    const std::string words = folderOfOneRow(dir, "words");
    appendLine(words, csvLineOf(row));
    EXPECT_NE(tableError(words).find("row 2 (ct head|10|A1): bytes is 'many', not a number"), std::string::npos);

    row.set("bytes", "");
    const std::string sizeless = folderOfOneRow(dir, "sizeless");
    appendLine(sizeless, csvLineOf(row));
    EXPECT_NE(tableError(sizeless).find("row 2 (ct head|10|A1) is measured but has no size in bytes"),
              std::string::npos);

    const std::string twice = folderOfOneRow(dir, "twice");
    const std::string written = test::readBytes(twice + "/results.csv");
    appendLine(twice, written.substr(written.find('\n') + 1, written.size() - written.find('\n') - 2));
    EXPECT_NE(tableError(twice).find("row 2 repeats row 1 (ct head|10|gvr)"), std::string::npos);

    const std::string foreign = folderOfOneRow(dir, "foreign");
    EXPECT_NE(tableError(foreign, {"A1", "zfp-rate"}).find("is of method 'gvr', which neither gvr nor the manifest's"),
              std::string::npos);
    EXPECT_EQ(tableError(foreign, {"gvr"}), "");
}

TEST(BenchTable, LinksAndFoldersInPlaceOfTheBenchsFilesAreRefused) {
    test::TempDir dir;
    std::ofstream(dir.path("notes.txt")) << "a user's notes";
    const std::string linked = folderOfOneRow(dir, "linked");
    std::filesystem::remove(linked + "/results.json");
    std::filesystem::create_symlink(dir.path("notes.txt"), linked + "/results.json");
    EXPECT_NE(tableError(linked).find("linked/results.json: is a symbolic link"), std::string::npos);
    EXPECT_EQ(test::readBytes(dir.path("notes.txt")), "a user's notes");

    const std::string script = folderOfOneRow(dir, "script");
    std::filesystem::create_symlink(dir.path("notes.txt"), script + "/bench_report.py");
    EXPECT_NE(tableError(script).find("script/bench_report.py: is a symbolic link"), std::string::npos);

    const std::string csv = folderOfOneRow(dir, "csv");
    std::filesystem::rename(csv + "/results.csv", dir.path("elsewhere.csv"));
    std::filesystem::create_symlink(dir.path("elsewhere.csv"), csv + "/results.csv");
    EXPECT_NE(tableError(csv).find("is a symbolic link"), std::string::npos);

    const std::string folder = folderOfOneRow(dir, "folder");
    std::filesystem::remove(folder + "/results.json");
    std::filesystem::create_directory(folder + "/results.json");
    EXPECT_NE(tableError(folder).find("folder/results.json: is not a regular file as the bench writes it"),
              std::string::npos);

    std::filesystem::create_directories(dir.path("runs-elsewhere"));
    std::filesystem::create_directories(dir.path("below/runs"));
    std::filesystem::create_symlink(dir.path("runs-elsewhere"), dir.path("below/runs/ch2"));
    EXPECT_NE(test::errorMessageOf<InputError>([&] {
                  refuseLinksBelow(dir.path("below"), dir.path("below/runs/ch2/r10/gvr"));
              }).find("below/runs/ch2: is a symbolic link"),
              std::string::npos);
    EXPECT_NO_THROW(refuseLinksBelow(dir.path("below"), dir.path("below/runs/other/r10/gvr")));
}

TEST(BenchTable, AResultsCsvLargerThanABenchWritesIsRefusedUnread) {
    test::TempDir dir;
    const std::string folder = folderOfOneRow(dir, "huge");
    std::filesystem::resize_file(folder + "/results.csv", std::uintmax_t(1) << 32);  // sparse: no disk used
    EXPECT_NE(tableError(folder).find("results.csv: is 4294967296 bytes, more than a bench writes (64 MiB at most)"),
              std::string::npos);
}

// Two benches appending to one results.csv wrote each row twice.
TEST(BenchTable, OneBenchAtATimeHoldsAFolder) {
    test::TempDir dir;
    const std::string folder = folderOfOneRow(dir, "busy");
    {
        ResultsTable first(folder, "m.json", /*resume=*/true);
        EXPECT_NE(tableError(folder).find("busy: is in use by another gvr bench"), std::string::npos);
    }
    EXPECT_EQ(tableError(folder), "");
}

TEST(BenchTable, TheManifestsDigestTellsManifestsApartWhereverTheyLie) {
    test::TempDir dir;
    std::ofstream(dir.path("a.json")) << R"({"volumes": [{"input": "a.nii"}]})";
    std::ofstream(dir.path("b.json")) << R"({"volumes": [{"input": "b.nii"}]})";
    std::filesystem::create_directory(dir.path("moved"));
    std::filesystem::copy(dir.path("a.json"), dir.path("moved/a.json"));
    EXPECT_EQ(manifestRecordOf(dir.path("a.json")).digest, manifestRecordOf(dir.path("moved/a.json")).digest);
    EXPECT_NE(manifestRecordOf(dir.path("a.json")).digest, manifestRecordOf(dir.path("b.json")).digest);
    EXPECT_EQ(manifestRecordOf(dir.path("a.json")).digest.size(), 8u);
    { ResultsTable table(dir.path("out"), dir.path("a.json"), false); }
    const ManifestRecord recorded = recordedManifest(dir.path("out/results.json"));
    EXPECT_EQ(recorded.path, dir.path("a.json"));
    EXPECT_EQ(recorded.digest, manifestRecordOf(dir.path("a.json")).digest);
}

// Resumed after the manifest was edited in place, a folder once kept rows run with its old budgets.
TEST(BenchTable, ResumeFollowsTheManifestsTextNotItsPath) {
    test::TempDir dir;
    std::ofstream(dir.path("m.json")) << R"({"fit": {"seconds": 60}, "volumes": [{"input": "a.nii"}]})";
    { ResultsTable table(dir.path("out"), dir.path("m.json"), false); }
    std::filesystem::create_directory(dir.path("moved"));
    std::filesystem::copy(dir.path("m.json"), dir.path("moved/m.json"));
    EXPECT_NO_THROW(ResultsTable(dir.path("out"), dir.path("moved/m.json"), /*resume=*/true));
    std::ofstream(dir.path("m.json")) << R"({"fit": {"seconds": 600}, "volumes": [{"input": "a.nii"}]})";
    const std::string message =
        test::errorMessageOf<InputError>([&] { ResultsTable(dir.path("out"), dir.path("m.json"), /*resume=*/true); });
    EXPECT_NE(message.find("out: holds the results of " + dir.path("moved/m.json") + " as it was (CRC-32 "),
              std::string::npos)
        << message;
}
