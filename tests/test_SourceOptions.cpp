// The source flags of ingest and info: what CLI11 parses into SourceFlags, and how
// toIngestOptions() checks them together and refuses, naming the flag.

#include "cli/Diagnostics.h"
#include "cli/SourceOptions.h"
#include "pipeline/Error.h"
#include "tests/ParseFlags.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace gvr {
namespace {

std::string refusal(const SourceFlags& flags) {
    return inCommandLineTerms(test::errorMessageOf<InputError>([&] { toIngestOptions(flags); }));
}

TEST(SourceOptions, NoFlagsReadTheFileAsItSays) {
    SourceFlags flags;
    CLI::App app;
    addSourceFlags(app, flags);
    test::parseFlags(app, {});
    const IngestOptions options = toIngestOptions(flags);
    EXPECT_EQ(options.read.volumeIndex, 0);
    EXPECT_FALSE(options.read.spacingMm);
    EXPECT_FALSE(options.read.raw);
    EXPECT_FALSE(options.read.dataFilesAnywhere);
    EXPECT_FALSE(options.build.threshold);
    EXPECT_FALSE(options.build.thresholdAbove);
    EXPECT_EQ(options.build.flip, (std::array<bool, 3>{false, false, false}));
    EXPECT_FALSE(options.build.nanTo);
    EXPECT_EQ(options.build.modality, "");
}

TEST(SourceOptions, EveryFlagReachesTheIngestOptions) {
    SourceFlags flags;
    CLI::App app;
    addSourceFlags(app, flags);
    test::parseFlags(app, {"--volume",
                           "2",
                           "--spacing",
                           "0.5,0.75,2",
                           "--raw-dims",
                           "4,5,6",
                           "--raw-type",
                           "int16",
                           "--endian",
                           "big",
                           "--header-bytes",
                           "352",
                           "--raw-channels",
                           "3",
                           "--threshold",
                           "10",
                           "--threshold-above",
                           "200",
                           "--flip",
                           "j,k",
                           "--nan-to",
                           "-1",
                           "--modality",
                           "CT",
                           "--data-files-anywhere"});
    const IngestOptions options = toIngestOptions(flags);
    EXPECT_EQ(options.read.volumeIndex, 2);
    ASSERT_TRUE(options.read.spacingMm);
    EXPECT_EQ(*options.read.spacingMm, openvdb::Vec3d(0.5, 0.75, 2.0));
    ASSERT_TRUE(options.read.raw);
    EXPECT_EQ(options.read.raw->dims, (std::array<std::int64_t, 3>{4, 5, 6}));
    EXPECT_EQ(options.read.raw->type, SampleType::Int16);
    EXPECT_EQ(options.read.raw->channels, 3);
    EXPECT_TRUE(options.read.raw->bigEndian);
    EXPECT_EQ(options.read.raw->headerBytes, 352u);
    EXPECT_TRUE(options.read.dataFilesAnywhere);
    EXPECT_EQ(options.build.threshold, 10.0);
    EXPECT_EQ(options.build.thresholdAbove, 200.0);
    EXPECT_EQ(options.build.flip, (std::array<bool, 3>{false, true, true}));
    EXPECT_EQ(options.build.nanTo, -1.0f);
    EXPECT_EQ(options.build.modality, "CT");
}

TEST(SourceOptions, WithoutThresholdTheCommandKeepsThatFlag) {
    // eval gives --threshold a meaning of its own.
    SourceFlags flags;
    CLI::App app;
    addSourceFlags(app, flags, /*withThreshold=*/false);
    EXPECT_TRUE(app.get_option_no_throw("--threshold") == nullptr);
    EXPECT_TRUE(app.get_option_no_throw("--threshold-above") == nullptr);
    EXPECT_TRUE(app.get_option_no_throw("--nan-to") != nullptr);
}

TEST(SourceOptions, ChoicesAreCheckedWhileParsing) {
    for (const std::vector<const char*>& bad :
         std::vector<std::vector<const char*>>{{"--endian", "middle"}, {"--raw-channels", "2"}, {"--volume", "-1"}}) {
        SourceFlags flags;
        CLI::App app;
        addSourceFlags(app, flags);
        EXPECT_THROW(test::parseFlags(app, bad), CLI::ParseError) << bad[0] << " " << bad[1];
    }
}

TEST(SourceOptions, RawFlagsComeTogether) {
    SourceFlags dimsOnly;
    dimsOnly.rawDims = {2, 2, 2};
    EXPECT_EQ(refusal(dimsOnly), "--raw-dims: needs --raw-type as well");
    SourceFlags typeOnly;
    typeOnly.rawType = "uint8";
    EXPECT_EQ(refusal(typeOnly), "--raw-type: needs --raw-dims as well");
    SourceFlags unknownType = dimsOnly;
    unknownType.rawType = "uint12";
    EXPECT_EQ(refusal(unknownType).rfind("--raw-type: unsupported sample type 'uint12'", 0), 0u)
        << refusal(unknownType);
}

TEST(SourceOptions, BadValuesAreRefusedNamingTheFlag) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    SourceFlags spacing;
    spacing.spacing = {1.0, 0.0, 1.0};
    EXPECT_EQ(refusal(spacing), "--spacing: each voxel size must be a positive number of mm");
    spacing.spacing = {1.0, nan, 1.0};
    EXPECT_EQ(refusal(spacing), "--spacing: each voxel size must be a positive number of mm");

    SourceFlags threshold;
    threshold.threshold = nan;
    EXPECT_EQ(refusal(threshold), "--threshold: must be a finite number");
    threshold.threshold = 100.0;
    threshold.thresholdAbove = 100.0;
    EXPECT_EQ(refusal(threshold), "--threshold-above: must lie above --threshold, or nothing stays active");
    threshold.thresholdAbove = std::numeric_limits<double>::infinity();
    EXPECT_EQ(refusal(threshold), "--threshold-above: must be a finite number");

    SourceFlags flip;
    flip.flip = "j,x";
    EXPECT_EQ(refusal(flip), "--flip: 'x' is no index axis: give i, j and/or k, comma-separated");
    flip.flip = "j,";
    EXPECT_EQ(refusal(flip), "--flip: 'j,' ends with a comma: give i, j and/or k, comma-separated");

    SourceFlags nanTo;
    nanTo.nanTo = std::numeric_limits<float>::infinity();
    EXPECT_EQ(refusal(nanTo), "--nan-to: must be a finite number, of float32's range (at most 3.4e38 in magnitude)");
}

}  // namespace
}  // namespace gvr
