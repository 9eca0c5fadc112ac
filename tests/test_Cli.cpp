// The gvr executable as a user meets it: exit codes, one-line errors, no stray files.

#include "tests/TestHelpers.h"

#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace gvr {
namespace {

/// The gantry-tilted CT of the shared data, ingested into @a dir: a real scan of
/// 7 M voxels whose fits take seconds.
/// `gvr fit` of the shear CT, ingested into @a dir, into ct.gvr with @a flags.
std::string shearCtFit(const test::TempDir& dir, const std::string& flags) {
    const std::string grid = dir.path("ct.vdb");
    const test::CommandResult run = test::runGvr(
        "ingest -q '" + test::sharedData("ct-gantry-tilt-shear/shear.nii.gz") + "' -o '" + grid + "'", dir);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(std::filesystem::exists(grid));
    return "fit -q '" + grid + "' -o '" + dir.path("ct.gvr") + "' " + flags;
}

TEST(Cli, HelpOnEveryCommand) {
    test::TempDir dir;
    for (const char* command : {"--help", "ingest --help", "info --help", "fit --help", "export --help", "eval --help",
                                "probe --help", "merge --help"}) {
        const test::CommandResult run = test::runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 0) << command;
        EXPECT_NE(run.out.find("Usage"), std::string::npos) << command;
    }
    EXPECT_NE(test::runGvr("ingest --help", dir).out.find("--threshold"), std::string::npos);
    const std::string fitHelp = test::runGvr("fit --help", dir).out;
    for (const char* ablation : {"full", "A1", "A2", "A3", "A4", "A5"}) {
        EXPECT_NE(fitHelp.find(ablation), std::string::npos) << ablation;
    }
    // Sixty options read in groups, not as one list.
    for (const char* group : {"Budget and output:", "Slice curriculum:", "Asset encoding:", "Bricks"}) {
        EXPECT_NE(fitHelp.find(group), std::string::npos) << group;
    }
}

TEST(Cli, BadInputGivesOneLineExitTwoAndNoOutput) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string cut = dir.path("cut.nii.gz");
    test::copyTruncated(test::sharedData("mri-colin27-aal/ch2.nii.gz"), cut, 50000);
    std::filesystem::create_directory(dir.path("out"));
    const test::CommandResult run = test::runGvr("ingest '" + cut + "' -o '" + dir.path("out/x.vdb") + "'", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
    EXPECT_EQ(run.err.rfind("gvr: error: " + cut + ": ", 0), 0u) << run.err;
    EXPECT_TRUE(std::filesystem::is_empty(dir.path("out")));
}

// nifticlib prints "** ERROR: ..." on its own before it returns a failure.
TEST(Cli, LibraryMessagesStayOffStderrUnlessVerbose) {
    test::TempDir dir;
    std::string header(352, '\0');  // a NIfTI-1 header whose dim[0] is out of range
    const std::int32_t headerSize = 348;
    const std::int16_t rank = 9;
    const float voxOffset = 352.0f;
    std::memcpy(&header[0], &headerSize, sizeof headerSize);
    std::memcpy(&header[40], &rank, sizeof rank);
    std::memcpy(&header[108], &voxOffset, sizeof voxOffset);
    std::memcpy(&header[344], "n+1", 4);
    const std::string input = dir.path("bad.nii");
    test::writeBytes(input, header);
    const std::string command = "ingest '" + input + "' -o '" + dir.path("x.vdb") + "'";

    const test::CommandResult quiet = test::runGvr(command, dir);
    EXPECT_EQ(quiet.exitCode, 2);
    EXPECT_EQ(test::lineCount(quiet.err), 1u) << quiet.err;
    EXPECT_EQ(quiet.err.rfind("gvr: error: " + input + ": ", 0), 0u) << quiet.err;

    const test::CommandResult verbose = test::runGvr(command + " --verbose", dir);
    EXPECT_EQ(verbose.exitCode, 2);
    EXPECT_EQ(verbose.err.rfind("gvr: error: " + input + ": ", 0), 0u) << verbose.err;
    EXPECT_NE(verbose.err.find("\ngvr: library: ** ERROR: nifti_convert_n1hdr2nim: bad dim[0]"), std::string::npos)
        << verbose.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.vdb")));
}

TEST(Cli, HelpCommandAndShortVersion) {
    test::TempDir dir;
    const test::CommandResult help = test::runGvr("help", dir);
    EXPECT_EQ(help.exitCode, 0) << help.err;
    EXPECT_NE(help.out.find("Subcommands"), std::string::npos) << help.out;
    const test::CommandResult fitHelp = test::runGvr("help fit", dir);
    EXPECT_EQ(fitHelp.exitCode, 0) << fitHelp.err;
    EXPECT_EQ(fitHelp.out, test::runGvr("fit --help", dir).out);
    const test::CommandResult version = test::runGvr("-V", dir);
    EXPECT_EQ(version.exitCode, 0);
    EXPECT_EQ(version.out.rfind("gvr ", 0), 0u) << version.out;
    const test::CommandResult unknown = test::runGvr("help fitt", dir);
    EXPECT_EQ(unknown.exitCode, 2);
    EXPECT_NE(unknown.err.find("'fit'"), std::string::npos) << unknown.err;
}

TEST(Cli, MistypedCommandsAndFlagsGetASuggestion) {
    test::TempDir dir;
    const test::CommandResult command = test::runGvr("fitt x.vdb -o y.gvr", dir);
    EXPECT_EQ(command.exitCode, 2);
    EXPECT_EQ(test::lineCount(command.err), 1u) << command.err;
    EXPECT_NE(command.err.find("did you mean 'fit'"), std::string::npos) << command.err;
    const test::CommandResult flag = test::runGvr("fit x.vdb -o y.gvr --tim 5", dir);
    EXPECT_EQ(flag.exitCode, 2);
    EXPECT_NE(flag.err.find("did you mean --time?"), std::string::npos) << flag.err;
    EXPECT_EQ(test::runGvr("bogus", dir).err.find("did you mean"), std::string::npos);  // nothing near
}

TEST(Cli, InfoWarnsOnStderrLikeEveryCommand) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const test::CommandResult run =
        test::runGvr("info '" + test::sharedData("mri-4d-asl-float32/mpld_asl.nii.gz") + "'", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(run.out.find("warning"), std::string::npos) << run.out;
    EXPECT_NE(run.err.find("gvr: warning: 4D series"), std::string::npos) << run.err;
}

TEST(Cli, ChestCtKeepsItsLungsByDefaultAndAThresholdThatDeletesThemIsWarnedAbout) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string chest = test::sharedData("ct-chest-ricord-512");
    const test::CommandResult old =
        test::runGvr("ingest -q '" + chest + "' -o '" + dir.path("a.vdb") + "' --threshold -500", dir);
    ASSERT_EQ(old.exitCode, 0) << old.err;
    EXPECT_NE(old.err.find("gvr: warning: the threshold -500.0 HU leaves"), std::string::npos) << old.err;
    EXPECT_NE(old.err.find("--threshold -950"), std::string::npos) << old.err;

    const test::CommandResult fresh =
        test::runGvr("ingest -q '" + chest + "' -o '" + dir.path("b.vdb") + "' --json", dir);
    ASSERT_EQ(fresh.exitCode, 0) << fresh.err;
    EXPECT_EQ(fresh.err.find("warning"), std::string::npos) << fresh.err;
    const nlohmann::json metadata = nlohmann::json::parse(fresh.out)["grid"]["metadata"];
    EXPECT_EQ(metadata["gvr_threshold"], -950.0);
    // Air, not an average of air and the scanner's -3024 padding, is what inactive voxels hold.
    EXPECT_EQ(metadata["gvr_padding_value"], -3024.0);
    EXPECT_NEAR(metadata["gvr_background"].get<double>(), -1000.0, 30.0);
}

// A NIfTI reads as a copy of the source: the chest's 21.7 M voxels of air and padding
// became the grid's background in one without a word.
TEST(Cli, ANiftiOfAThresholdedGridSaysSo) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string chest = test::sharedData("ct-chest-ricord-512");
    const test::CommandResult thresholded =
        test::runGvr("ingest -q '" + chest + "' -o '" + dir.path("a.nii.gz") + "'", dir);
    ASSERT_EQ(thresholded.exitCode, 0) << thresholded.err;
    EXPECT_NE(
        thresholded.err.find("gvr: warning: " + dir.path("a.nii.gz") +
                             " holds the ingested grid, not a copy of the source: its 21669383 voxels outside the "
                             "threshold hold the grid's background -986.5"),
        std::string::npos)
        << thresholded.err;
    EXPECT_NE(thresholded.err.find("a --threshold below the data's minimum (-3024) keeps every value"),
              std::string::npos);
    const test::CommandResult faithful =
        test::runGvr("ingest -q '" + chest + "' -o '" + dir.path("b.nii.gz") + "' --threshold -5000", dir);
    ASSERT_EQ(faithful.exitCode, 0) << faithful.err;
    EXPECT_EQ(faithful.err.find("warning"), std::string::npos) << faithful.err;
}

TEST(Cli, UnknownFlagsAndBadSpacingAreUsageErrors) {
    test::TempDir dir;
    for (const char* bad : {"--flip x", "--flip i,q", "--threshold 10 --threshold-above 5"}) {
        const test::CommandResult run =
            test::runGvr(std::string("ingest x.raw -o y.vdb --raw-dims 2,2,2 --raw-type uint8 ") + bad, dir);
        EXPECT_EQ(run.exitCode, 2) << bad;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
    }
    EXPECT_EQ(test::runGvr("ingest x.nii -o y.vdb --no-such-flag", dir).exitCode, 2);
    const test::CommandResult run =
        test::runGvr("ingest x.raw -o y.vdb --raw-dims 2,2,2 --raw-type uint8 --spacing 1,0,1", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.err.find("--spacing"), std::string::npos) << run.err;
}

TEST(Cli, IngestStreamsARawVolumeInLessMemoryThanHalfItsSamples) {
    // 1024 x 1024 x 512 uint8, 512 MiB of samples: zero but for a 64^3 cube of 200s.
    // The file is sparse, so writing it costs no disk.
    test::TempDir dir;
    const std::string raw = dir.path("big.raw");
    {
        std::ofstream out(raw, std::ios::binary);
        const std::string row(64, char(200));
        for (int k = 300; k < 364; ++k) {
            for (int j = 500; j < 564; ++j) {
                out.seekp(std::streamoff((std::int64_t(k) * 1024 + j) * 1024 + 400));
                out.write(row.data(), std::streamsize(row.size()));
            }
        }
    }
    std::filesystem::resize_file(raw, std::uintmax_t(1024) * 1024 * 512);
    const test::CommandResult run = test::runGvr(
        "ingest '" + raw + "' --raw-dims 1024,1024,512 --raw-type uint8 -o '" + dir.path("big.vdb") + "' --json -q",
        dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["grid"]["active_voxels"], 64 * 64 * 64);
    EXPECT_LT(report["peak_rss_mib"].get<double>(), 256.0) << "MiB of peak memory for 512 MiB of samples";
}

TEST(Cli, FileNamesThatAreNotUtf8StayInTheJsonReports) {
    // A Linux file name may hold any byte but '/' and NUL: "x\xff.vdb" made every
    // --json report an internal error (invalid UTF-8), after the output was written.
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string latin1 = dir.path(
        "sch\xe4"
        "del.vdb");
    const test::CommandResult ingest = test::runGvr("ingest -q '" + grid + "' -o '" + latin1 + "' --json", dir);
    ASSERT_EQ(ingest.exitCode, 0) << ingest.err;
    EXPECT_EQ(nlohmann::json::parse(ingest.out)["outputs"][0]["path"], dir.path("sch\xef\xbf\xbd"
                                                                                "del.vdb"));
    const test::CommandResult info = test::runGvr("info '" + latin1 + "' --json", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    EXPECT_TRUE(nlohmann::json::accept(info.out)) << info.out;
}

TEST(Cli, IngestThenInfoAsJson) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string output = dir.path("ch2.vdb");
    const test::CommandResult ingested = test::runGvr(
        "ingest '" + test::sharedData("mri-colin27-aal/ch2.nii.gz") + "' -o '" + output + "' --threshold 20 --json",
        dir);
    ASSERT_EQ(ingested.exitCode, 0) << ingested.err;
    EXPECT_EQ(nlohmann::json::parse(ingested.out)["outputs"][0]["path"], output);

    const test::CommandResult info = test::runGvr("info --json '" + output + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    const nlohmann::json report = nlohmann::json::parse(info.out);
    EXPECT_EQ(report["kind"], "vdb");
    EXPECT_EQ(report["file_bytes"], std::filesystem::file_size(output));
    const nlohmann::json& grid = report["grids"][0];
    EXPECT_EQ(grid["name"], "density");
    EXPECT_GT(grid["value_min"].get<double>(), 20.0);
    // Numbers as numbers, vectors as arrays, and the affine in NIfTI's column form.
    EXPECT_EQ(grid["metadata"]["gvr_threshold"], 20.0);
    EXPECT_EQ(grid["metadata"]["gvr_source_type"], "uint8");
    EXPECT_EQ(grid["metadata"]["gvr_dims"], nlohmann::json({181, 217, 181}));
    EXPECT_EQ(grid["affine"][0][0], 1.0) << grid["affine"];  // ch2: i runs along +x, 1 mm voxels
    EXPECT_EQ(grid["affine"][3], nlohmann::json({0.0, 0.0, 0.0, 1.0}));

    const test::CommandResult source =
        test::runGvr("info '" + test::sharedData("ct-gantry-tilt-shear/shear.nii.gz") + "'", dir);
    ASSERT_EQ(source.exitCode, 0) << source.err;
    EXPECT_NE(source.out.find("gvr ingest would write"), std::string::npos);
    EXPECT_NE(source.out.find("306 x"), std::string::npos) << source.out;
}

TEST(Cli, FitIsReproducibleByteForByteWhateverTheThreads) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string common = "fit -q '" + grid + "' --gaussians 120 --iterations 40 --seed 3 --batch 2048 ";
    ASSERT_EQ(test::runGvr(common + "-o '" + dir.path("a.asset") + "'", dir).exitCode, 0);
    ASSERT_EQ(test::runGvr(common + "-o '" + dir.path("b.asset") + "' --threads 1", dir).exitCode, 0);
    const std::string a = test::readBytes(dir.path("a.asset")), b = test::readBytes(dir.path("b.asset"));
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, b);

    const test::CommandResult info = test::runGvr("info --json '" + dir.path("a.asset") + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    const nlohmann::json report = nlohmann::json::parse(info.out);
    EXPECT_EQ(report["gaussians"], 120);
    EXPECT_EQ(report["raw_source_bytes"], 24 * 20 * 16);
}

TEST(Cli, FitRespectsTheRatioAndLogsErrorAgainstTime) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const test::CommandResult run =
        test::runGvr("fit -q '" + grid + "' -o '" + dir.path("r.asset") +
                         "' --ratio 4 --iterations 60 --log-every 20 --log '" + dir.path("fit.csv") + "' --json",
                     dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_LE(std::filesystem::file_size(dir.path("r.asset")), 24u * 20 * 16 / 4);
    const nlohmann::json result = nlohmann::json::parse(run.out);
    EXPECT_GT(result["psnr_db"].get<double>(), 20.0);
    // Plain CSV: the header first, then numbers only, as any reader expects.
    const std::string log = test::readBytes(dir.path("fit.csv"));
    EXPECT_EQ(log.rfind("iteration,seconds,loss,psnr_db,gaussians,peak_rss_mib,gradient_share\n", 0), 0u) << log;
    EXPECT_EQ(log.find_first_not_of("0123456789.,-+einf\n", log.find('\n')), std::string::npos) << log;
    EXPECT_EQ(test::lineCount(log), 1u + 3u + 1u);  // header, 3 evaluations, the amplitude solve's
    EXPECT_GT(result["amplitude_solve"]["iterations"].get<int>(), 0);
}

TEST(Cli, FitForATimeStopsOnTimeWithinTheRatio) {
    // Every figure in the README comes from --time fits: the budget covers the
    // amplitude solve, and the count stays within what the ratio allows.
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const test::CommandResult run =
        test::runGvr("fit -q '" + grid + "' -o '" + dir.path("t.asset") + "' --ratio 4 --time 3 --json", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json result = nlohmann::json::parse(run.out);
    // Not a speed test: a fit that ignored its budget would be off by far more.
    EXPECT_GT(result["seconds"].get<double>(), 1.5);
    EXPECT_LT(result["seconds"].get<double>(), 3.0 + 10.0);
    EXPECT_GT(result["iterations"].get<int>(), 10);
    EXPECT_LE(std::filesystem::file_size(dir.path("t.asset")), 24u * 20 * 16 / 4);
    EXPECT_GT(result["psnr_db"].get<double>(), 20.0);
}

TEST(Cli, TheTimeBudgetCoversTheFitTheSolveAndTheMeasurement) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const test::CommandResult run = test::runGvr(shearCtFit(dir, "--ratio 20 --time 4 --json"), dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json result = nlohmann::json::parse(run.out);
    const nlohmann::json& phases = result["phase_seconds"];
    const double afterLoading = phases["total"].get<double>() - phases["load"].get<double>();
    // Not a speed test: before, the measurement alone came on top of the budget.
    EXPECT_LT(afterLoading, 4.0 * 1.25 + 0.5) << phases.dump();
    EXPECT_GT(phases["measure"].get<double>(), 0.0);
    // 10 % of 4 s holds no three dense passes of this CT: the solve says it was
    // skipped, where it reported 0 iterations and PSNRs of "inf".
    const nlohmann::json& solve = result["amplitude_solve"];
    ASSERT_TRUE(solve["skipped"].is_string()) << solve.dump();
    EXPECT_NE(solve["skipped"].get<std::string>().find("holds fewer than the 3 dense passes"), std::string::npos);
    EXPECT_TRUE(solve["psnr_before_db"].is_null());
    EXPECT_TRUE(solve["psnr_after_db"].is_null());
}

TEST(Cli, ABudgetShorterThanTheVolumesFixedCostsSaysSoOnOneLine) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    // The dense measurement of this CT alone outlasts a tenth of a second.
    const test::CommandResult run = test::runGvr(shearCtFit(dir, "--ratio 20 --time 0.1"), dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const std::size_t start = run.err.find("gvr: warning: the fit took ");
    ASSERT_NE(start, std::string::npos) << run.err;
    const std::string line = run.err.substr(start, run.err.find('\n', start) - start);
    EXPECT_NE(line.find(" s after reading, over --time 0.1: on this volume the set-up alone takes "), std::string::npos)
        << run.err;
    EXPECT_NE(line.find(" s and the final measurement "), std::string::npos) << run.err;
}

TEST(Cli, AShortFitKeepsTheRatiosCountAndSaysOnOneLineWhatTimeWouldTrainIt) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    // 8:1, whose 135,000 Gaussians 6 s leaves at 240 samples each on an idle 2-core
    // machine (20:1 got 1,100, trained). The sanitizers' build skips this test: its
    // set-up leaves no iteration in 6 s (.ci/sanitize.sh).
    const std::string fit = shearCtFit(dir, "--ratio 8 --time 6 --json");
    const test::CommandResult kept = test::runGvr(fit, dir);
    ASSERT_EQ(kept.exitCode, 0) << kept.err;
    const nlohmann::json result = nlohmann::json::parse(kept.out);
    // Before, the time chose the count: the chest at 20:1 for 120 s wrote 135:1. Now
    // the count is the ratio's and the file within its bytes.
    EXPECT_EQ(result["gaussians_allowed_by_ratio"].get<std::size_t>(), 0u);
    EXPECT_GE(result["ratio_vs_raw"].get<double>(), 8.0 * 0.999);
    ASSERT_TRUE(result["undertrained"].is_string());
    const std::size_t start = kept.err.find("gvr: warning: undertrained: 6 s gave each of the ");
    ASSERT_NE(start, std::string::npos) << kept.err;
    const std::string line = kept.err.substr(start, kept.err.find('\n', start) - start);
    EXPECT_NE(line.find(" s would give each 1000 (--min-samples 1000 "), std::string::npos) << kept.err;

    const test::CommandResult traded = test::runGvr(fit + " --min-samples 1000000", dir);
    ASSERT_EQ(traded.exitCode, 0) << traded.err;
    const nlohmann::json fewer = nlohmann::json::parse(traded.out);
    // The count the ratio allows, which the default fit started from: it then added
    // where the file had room, and the writer dropped any that no longer fitted.
    // The two headers differ by the digits of min_samples (and hold the path of this
    // temporary folder), which can cost the traded fit's allowance one Gaussian.
    const std::size_t started = result["gaussians"].get<std::size_t>() +
                                result["dropped_to_fit_budget"].get<std::size_t>() -
                                result["added_to_fill_budget"].get<std::size_t>();
    const std::size_t allowed = fewer["gaussians_allowed_by_ratio"].get<std::size_t>();
    EXPECT_GE(started, allowed);
    EXPECT_LE(started, allowed + 1);
    EXPECT_GT(fewer["ratio_vs_raw"].get<double>(), 2.0 * result["ratio_vs_raw"].get<double>());
}

TEST(Cli, AFewStepsFillTheRoomThatBarelyMovedSeedsLeaveInTheFile) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    // Iterations, not seconds, so that both fill points come however slow the build.
    const test::CommandResult run = test::runGvr(shearCtFit(dir, "--ratio 20 --iterations 10 --json"), dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json result = nlohmann::json::parse(run.out);
    // Seeds code smaller than the size model expects: 22.2:1 (3 s) before the fit
    // filled the room they leave.
    EXPECT_GT(result["added_to_fill_budget"].get<std::size_t>(), 0u);
    EXPECT_GE(result["ratio_vs_raw"].get<double>(), 20.0 * 0.999);
    EXPECT_LE(result["ratio_vs_raw"].get<double>(), 20.0 * 1.05);
}

TEST(Cli, BadAssetEncodingAndSolveFlagsAreRefusedWithoutOutput) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    for (const std::string flag :
         {"--mean-step 0", "--rotation-bits 1", "--scale-bits 17", "--amplitude-bits 40", "--solve-share 1.5"}) {
        const test::CommandResult run =
            test::runGvr("fit -q '" + grid + "' -o '" + dir.path("bad.gvr") + "' --iterations 5 " + flag, dir);
        EXPECT_EQ(run.exitCode, 2) << flag;
        EXPECT_NE(run.err.find(flag.substr(0, flag.find(' '))), std::string::npos) << run.err;
        EXPECT_FALSE(std::filesystem::exists(dir.path("bad.gvr"))) << flag;
    }
}

TEST(Cli, NegativeCountsAreRefusedNotWrapped) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    for (const std::string flag :
         {"--gaussians -5", "--gaussians 0", "--iterations -1", "--seed -1", "--refresh-every -1", "--batch -1",
          "--held-out -1", "--slice-pixels -1", "--threads -1", "--threads 100000"}) {
        const std::string budget = flag.rfind("--iterations", 0) == 0 ? "" : "--iterations 5 ";
        const test::CommandResult run =
            test::runGvr("fit -q '" + grid + "' -o '" + dir.path("bad.gvr") + "' " + budget + flag, dir);
        EXPECT_EQ(run.exitCode, 2) << flag;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_EQ(run.err.rfind("gvr: error: ", 0), 0u) << run.err;
        EXPECT_NE(run.err.find(flag.substr(0, flag.find(' '))), std::string::npos) << run.err;
        EXPECT_FALSE(std::filesystem::exists(dir.path("bad.gvr"))) << flag;
    }
}

TEST(Cli, OutputsNeverReplaceInputsOrSpecialFiles) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string before = test::readBytes(grid);
    const std::string fifo = dir.path("pipe.gvr");
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    std::filesystem::create_directory(dir.path("out"));
    const std::string asset = dir.path("out/a.gvr");
    for (const std::string& command :
         {"fit -q '" + grid + "' -o '" + grid + "' --iterations 5", "ingest '" + grid + "' -o '" + grid + "'",
          "fit -q '" + grid + "' -o '" + fifo + "' --iterations 5",
          "fit -q '" + grid + "' -o '" + dir.path("out") + "' --iterations 5",
          "fit -q '" + grid + "' -o '" + asset + "' --iterations 5 --log '" + grid + "'",
          "render '" + grid + "' -o '" + dir.path("out/x.png") + "' --stats '" + dir.path("missing/stats.json") +
              "'"}) {
        const test::CommandResult run = test::runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 2) << command << "\n" << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
    }
    EXPECT_EQ(test::readBytes(grid), before) << "an input was overwritten";
    EXPECT_TRUE(std::filesystem::is_fifo(fifo)) << "the FIFO was replaced by a file";
    EXPECT_TRUE(std::filesystem::is_empty(dir.path("out"))) << "a refused command left a file";
}

TEST(Cli, EvalsDifferenceImageNeverReplacesAnInput) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string reference = dir.path("a.png"), copy = dir.path("b.png");
    ASSERT_EQ(test::runGvr("render -q '" + grid + "' -o '" + reference + "' --size 32x32", dir).exitCode, 0);
    std::filesystem::copy_file(reference, copy);
    const std::string before = test::readBytes(reference);
    for (const std::string& target : {reference, copy}) {
        // Before, --difference alone of eval's outputs went unchecked: exit 0, the reference replaced.
        const test::CommandResult run =
            test::runGvr("eval '" + reference + "' '" + copy + "' --difference '" + target + "'", dir);
        EXPECT_EQ(run.exitCode, 2) << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_NE(run.err.find("--difference " + target + ": is also an input"), std::string::npos) << run.err;
    }
    EXPECT_EQ(test::readBytes(reference), before);
    EXPECT_EQ(test::readBytes(copy), before);
}

TEST(Cli, NoOutputIsAFileThatAnInputReads) {
    // One rule for every path written against every file read: the members of a
    // series, a MetaImage's data file, a saved transfer function, orbit frames.
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    std::filesystem::create_directory(dir.path("series"));
    for (const char* slice : {"1-001.dcm", "1-002.dcm", "1-003.dcm"}) {
        std::filesystem::copy_file(test::sharedData(std::string("ct-chest-ricord-512/") + slice),
                                   dir.path(std::string("series/") + slice));
    }
    std::filesystem::rename(dir.path("series/1-002.dcm"), dir.path("series/s2.vdb"));  // DICOM by content, any name
    test::writeBytes(dir.path("vol.mhd"),
                     "ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_UCHAR\n"
                     "ElementDataFile = data.vdb\n");
    test::writeBytes(dir.path("data.vdb"), std::string(64, '\7'));
    test::writeBytes(dir.path("tf.json"), R"({"points": [[0, 0, 0, 0, 0], [100, 1, 1, 1, 0.5]]})");
    std::filesystem::create_directory(dir.path("frames"));
    test::writeBytes(dir.path("frames/f_0001.png"), "an input slice");
    const std::map<std::string, std::string> guarded = {
        {"series/s2.vdb", "ingest '" + dir.path("series") + "' -o '" + dir.path("series/s2.vdb") + "'"},
        {"data.vdb", "ingest '" + dir.path("vol.mhd") + "' -o '" + dir.path("data.vdb") + "'"},
        {"tf.json", "render '" + grid + "' -o '" + dir.path("x.png") + "' --tf '" + dir.path("tf.json") +
                        "' --stats '" + dir.path("tf.json") + "'"},
        {"small.vdb", "render '" + grid + "' -o '" + dir.path("y.png") + "' --save-tf '" + grid + "'"},
        {"frames/f_0001.png",
         "render '" + dir.path("frames/*.png") + "' --orbit 4 -o '" + dir.path("frames/f.png") + "'"},
    };
    for (const auto& [file, command] : guarded) {
        const std::string before = test::readBytes(dir.path(file));
        const test::CommandResult run = test::runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 2) << command << "\n" << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_TRUE(run.err.find("is also an input") != std::string::npos ||
                    run.err.find("is one of the files read from") != std::string::npos)
            << run.err;
        EXPECT_EQ(test::readBytes(dir.path(file)), before) << file << " was overwritten by: " << command;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.png")));
    EXPECT_FALSE(std::filesystem::exists(dir.path("y.png")));
}

TEST(Cli, InputsThatAreNotRegularFilesAreRefusedWithoutBlocking) {
    // A FIFO as an input once blocked forever, and /dev/zero as a manifest read forever.
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    for (const char* name : {"pipe.vdb", "pipe.nii.gz", "pipe.png", "pipe.gvr", "pipe.json", "pipe.txt"}) {
        ASSERT_EQ(mkfifo(dir.path(name).c_str(), 0600), 0);
    }
    const std::string out = " -o '" + dir.path("out.vdb") + "'";
    for (const std::string& command :
         {"ingest '" + dir.path("pipe.nii.gz") + "'" + out, "ingest '" + dir.path("pipe.png") + "'" + out,
          "ingest '" + dir.path("pipe*.png") + "'" + out, "info '" + dir.path("pipe.vdb") + "'",
          "info '" + dir.path("pipe.gvr") + "'", "eval '" + grid + "' '" + dir.path("pipe.vdb") + "'",
          "render '" + grid + "' -o '" + dir.path("x.png") + "' --tf '" + dir.path("pipe.json") + "'",
          "ingest '" + grid + "' --labels '" + grid + "' --label-names '" + dir.path("pipe.txt") + "'" + out,
          "bench /dev/zero -o '" + dir.path("bench") + "'",
          "bench '" + dir.path("pipe.json") + "' -o '" + dir.path("bench") + "'"}) {
        const test::CommandResult run =
            test::runGvr("--version >/dev/null; timeout 30 '" GVR_EXECUTABLE "' " + command, dir);
        EXPECT_EQ(run.exitCode, 2) << command << "\n" << run.err;
        EXPECT_NE(run.err.find("is not a regular file"), std::string::npos) << command << "\n" << run.err;
    }
}

TEST(Cli, AFailedFitLeavesNoLogAndStaleTemporariesAreCleared) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    // A temporary of a process that no longer runs (pid 999999999 never does), and one of a live process.
    const std::string stale = dir.path(".gvr-999999999-Ab3xYz"), live = dir.path(".gvr-1-Ab3xYz");
    for (const std::string& folder : {stale, live}) {
        std::filesystem::create_directory(folder);
        std::filesystem::permissions(folder, std::filesystem::perms::owner_all);
        test::writeBytes(folder + "/a.gvr", "left by SIGKILL, or being written by pid 1");
    }
    const test::CommandResult ok =
        test::runGvr("fit -q '" + grid + "' -o '" + dir.path("a.gvr") + "' --gaussians 40 --iterations 20 --log '" +
                         dir.path("a.csv") + "'",
                     dir);
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_FALSE(std::filesystem::exists(stale));
    EXPECT_TRUE(std::filesystem::exists(live));
    EXPECT_TRUE(std::filesystem::exists(dir.path("a.csv")));
    // A fit that fails after its log was opened: ulimit -f lets the log's few rows
    // through (512 bytes) but not the asset.
    const test::CommandResult failed =
        test::runGvr("--version >/dev/null; ulimit -f 1; '" GVR_EXECUTABLE "' fit -q '" + grid + "' -o '" +
                         dir.path("b.gvr") + "' --gaussians 60 --iterations 20 --log '" + dir.path("b.csv") + "'",
                     dir);
    EXPECT_EQ(failed.exitCode, 2) << failed.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("b.gvr")));
    EXPECT_FALSE(std::filesystem::exists(dir.path("b.csv"))) << "a failed fit left its log";
}

TEST(Cli, NumbersOutsideTheirRangeAreRefusedAndHugePeaksStayFinite) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string asset = dir.path("a.gvr");
    ASSERT_EQ(test::runGvr("fit -q '" + grid + "' -o '" + asset + "' --gaussians 40 --iterations 10", dir).exitCode, 0);
    for (const std::string& command :
         {"export '" + asset + "' -o '" + dir.path("x.vdb") + "' --threshold nan",
          "eval '" + grid + "' '" + asset + "' --threshold nan",
          "fit -q '" + grid + "' -o '" + dir.path("b.gvr") + "' --gaussians 40 --time 1e30",
          "fit -q '" + grid + "' -o '" + dir.path("b.gvr") + "' --gaussians 40 --iterations 18446744073709551615"}) {
        const test::CommandResult run = test::runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 2) << command << "\n" << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
    }
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.vdb")));
    EXPECT_FALSE(std::filesystem::exists(dir.path("b.gvr")));
    // A peak of 1e300 squared is infinite; the PSNR is not.
    const test::CommandResult huge = test::runGvr("eval --json '" + grid + "' '" + asset + "' --peak 1e300", dir);
    ASSERT_EQ(huge.exitCode, 0) << huge.err;
    const nlohmann::json psnr = nlohmann::json::parse(huge.out)["psnr"];
    ASSERT_TRUE(psnr.is_number()) << psnr;  // "inf" before
    EXPECT_GT(psnr.get<double>(), 5000.0);
}

TEST(Cli, FittingAnEmptyVolumeWarnsAndWritesAnEmptyAsset) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir, /*empty=*/true);
    const test::CommandResult run =
        test::runGvr("fit -q '" + grid + "' -o '" + dir.path("e.asset") + "' --iterations 5", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.err.find("no active voxels"), std::string::npos) << run.err;
    const test::CommandResult info = test::runGvr("info --json '" + dir.path("e.asset") + "'", dir);
    EXPECT_EQ(nlohmann::json::parse(info.out)["gaussians"], 0);
}

TEST(Cli, CorruptAssetIsAOneLineError) {
    test::TempDir dir;
    test::writeBytes(dir.path("bad.asset"), std::string("GVRASSET") + std::string(40, '\1'));
    const test::CommandResult run = test::runGvr("info '" + dir.path("bad.asset") + "'", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
}

}  // namespace
}  // namespace gvr
