// The gvr executable as a user meets it: exit codes, one-line errors, no stray files.

#include "TestHelpers.h"

#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <sstream>

namespace gvr {
namespace {

struct CommandResult {
    int exitCode = -1;
    std::string out, err;
};

/// Runs gvr with @a arguments (already shell-quoted where needed).
CommandResult runGvr(const std::string& arguments, const test::TempDir& dir) {
    const std::string outPath = dir.path("stdout.txt"), errPath = dir.path("stderr.txt");
    const std::string command = std::string("'") + GVR_EXECUTABLE + "' " + arguments + " >'" +
                                outPath + "' 2>'" + errPath + "' </dev/null";
    const int status = std::system(command.c_str());
    CommandResult run;
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = test::readBytes(outPath);
    run.err = test::readBytes(errPath);
    std::filesystem::remove(outPath);
    std::filesystem::remove(errPath);
    return run;
}

std::size_t lineCount(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

TEST(Cli, HelpOnEveryCommand) {
    test::TempDir dir;
    for (const char* command : {"--help", "ingest --help", "info --help"}) {
        const CommandResult run = runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 0) << command;
        EXPECT_NE(run.out.find("Usage"), std::string::npos) << command;
    }
    EXPECT_NE(runGvr("ingest --help", dir).out.find("--threshold"), std::string::npos);
}

TEST(Cli, BadInputGivesOneLineExitTwoAndNoOutput) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string cut = dir.path("cut.nii.gz");
    test::copyTruncated(test::sharedData("mri-colin27-aal/ch2.nii.gz"), cut, 50000);
    std::filesystem::create_directory(dir.path("out"));
    const CommandResult run = runGvr("ingest '" + cut + "' -o '" + dir.path("out/x.vdb") + "'", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_EQ(lineCount(run.err), 1u) << run.err;
    EXPECT_EQ(run.err.rfind("gvr: error: " + cut + ": ", 0), 0u) << run.err;
    EXPECT_TRUE(std::filesystem::is_empty(dir.path("out")));
}

TEST(Cli, UnknownFlagsAndBadSpacingAreUsageErrors) {
    test::TempDir dir;
    EXPECT_EQ(runGvr("ingest x.nii -o y.vdb --no-such-flag", dir).exitCode, 2);
    const CommandResult run = runGvr("ingest x.raw -o y.vdb --raw-dims 2,2,2 --raw-type uint8 --spacing 1,0,1", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.err.find("--spacing"), std::string::npos) << run.err;
}

TEST(Cli, IngestThenInfoAsJson) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string output = dir.path("ch2.vdb");
    const CommandResult ingested = runGvr("ingest '" + test::sharedData("mri-colin27-aal/ch2.nii.gz") +
                                    "' -o '" + output + "' --threshold 20 --json", dir);
    ASSERT_EQ(ingested.exitCode, 0) << ingested.err;
    EXPECT_EQ(nlohmann::json::parse(ingested.out)["output"], output);

    const CommandResult info = runGvr("info --json '" + output + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    const nlohmann::json report = nlohmann::json::parse(info.out);
    EXPECT_EQ(report["kind"], "vdb");
    EXPECT_EQ(report["file_bytes"], std::filesystem::file_size(output));
    const nlohmann::json& grid = report["grids"][0];
    EXPECT_EQ(grid["name"], "density");
    EXPECT_GT(grid["value_min"].get<double>(), 20.0);
    EXPECT_EQ(grid["metadata"]["gvr_threshold"], "20");
    EXPECT_EQ(grid["metadata"]["gvr_source_type"], "uint8");

    const CommandResult source = runGvr("info '" + test::sharedData("ct-gantry-tilt-shear/shear.nii.gz") + "'", dir);
    ASSERT_EQ(source.exitCode, 0) << source.err;
    EXPECT_NE(source.out.find("gvr ingest would write"), std::string::npos);
    EXPECT_NE(source.out.find("306 x"), std::string::npos) << source.out;
}

}  // namespace
}  // namespace gvr
