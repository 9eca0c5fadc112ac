// Benchmark results: rows survive a round trip through results.csv, and a row torn
// by a kill is dropped on resume.

#include "bench/BenchTable.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

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
