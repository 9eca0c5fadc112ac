// The -o rule that ingest and export share: the options, the removed --format and
// its message, and how written files are reported as JSON and as lines.

#include "cli/Diagnostics.h"
#include "cli/VolumeOutputOptions.h"
#include "pipeline/Error.h"
#include "tests/ParseFlags.h"
#include "tests/TestHelpers.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace gvr {
namespace {

struct Printed {
    std::string out, err;
};

/// What printWritten() says on stdout and on gvr's own stderr; the latter is caught
/// at its descriptor, as a user's terminal would receive it.
Printed printed(const std::vector<WrittenVolume>& written, const NiftiStorage& storage) {
    test::TempDir dir;
    const std::string errPath = dir.path("err");
    std::fflush(diagnosticsFile());
    const int saved = dup(diagnosticsFd());
    const int file = open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(file, diagnosticsFd());
    close(file);
    std::ostringstream out;
    std::streambuf* const console = std::cout.rdbuf(out.rdbuf());
    printWritten(written, storage);
    std::cout.rdbuf(console);
    diagnostics().flush();
    std::fflush(diagnosticsFile());
    dup2(saved, diagnosticsFd());
    close(saved);
    return {out.str(), test::readBytes(errPath)};
}

NiftiStorage int16Storage() {
    NiftiStorage storage;
    storage.type = SampleType::Int16;
    storage.slope = 2.0;
    storage.intercept = -1024.0;
    storage.codes.sform = 2;
    storage.codes.qform = 1;
    return storage;
}

TEST(VolumeOutputOptions, OutputsRepeatAndOneIsRequired) {
    std::vector<std::string> outputs;
    bool float32 = false;
    CLI::App app;
    addVolumeOutputOptions(app, outputs, float32);
    test::parseFlags(app, {"-o", "a.vdb", "--output", "b.nii.gz", "--float32"});
    EXPECT_EQ(outputs, (std::vector<std::string>{"a.vdb", "b.nii.gz"}));
    EXPECT_TRUE(float32);

    std::vector<std::string> none;
    bool unset = false;
    CLI::App bare;
    addVolumeOutputOptions(bare, none, unset);
    EXPECT_THROW(test::parseFlags(bare, {"--float32"}), CLI::RequiredError);
}

TEST(VolumeOutputOptions, RemovedFormatIsHiddenParsedAndThenRefused) {
    std::string format;
    CLI::App app;
    addRemovedFormatOption(app, format);
    EXPECT_EQ(app.help().find("--format"), std::string::npos) << app.help();
    test::parseFlags(app, {"--format", "nifti"});
    EXPECT_EQ(format, "nifti");
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { rejectRemovedFormat(format); }),
              "--format: was removed: the extension of -o chooses the format; for a VDB and a NIfTI pass "
              "-o OUT.vdb -o OUT.nii.gz");
    EXPECT_NO_THROW(rejectRemovedFormat(""));
}

TEST(VolumeOutputOptions, JsonGivesNiftiStorageOnlyForNifti) {
    const std::vector<WrittenVolume> written = {{"a.vdb", VolumeFileFormat::Vdb, 1234, 0},
                                                {"a.nii.gz", VolumeFileFormat::Nifti, 5678, 3}};
    NiftiStorage storage = int16Storage();
    const nlohmann::json files = toJson(written, storage);
    ASSERT_EQ(files.size(), 2u);
    EXPECT_EQ(files.at(0), (nlohmann::json{{"path", "a.vdb"}, {"format", "vdb"}, {"file_bytes", 1234}}));
    const nlohmann::json& nifti = files.at(1);
    EXPECT_EQ(nifti.at("format"), "nifti");
    EXPECT_EQ(nifti.at("file_bytes"), 5678);
    EXPECT_EQ(nifti.at("datatype"), "int16");
    EXPECT_EQ(nifti.at("scl_slope"), 2.0);
    EXPECT_EQ(nifti.at("scl_inter"), -1024.0);
    EXPECT_EQ(nifti.at("sform_code"), 2);
    EXPECT_EQ(nifti.at("qform_code"), 1);
    EXPECT_EQ(nifti.at("clamped_samples"), 3);
    EXPECT_FALSE(nifti.contains("float32_because"));

    storage.float32Reason = "the source is float64";
    EXPECT_EQ(toJson(written, storage).at(1).at("float32_because"), "the source is float64");
}

TEST(VolumeOutputOptions, PrintsALinePerFileAndWarnsOfClampedSamples) {
    const Printed run = printed(
        {{"a.vdb", VolumeFileFormat::Vdb, 2048, 0}, {"a.nii.gz", VolumeFileFormat::Nifti, 512, 3}}, int16Storage());
    EXPECT_EQ(run.out,
              "wrote a.vdb (2 KiB)\n"
              "wrote a.nii.gz (512 B): NIfTI, int16, scl_slope 2, scl_inter -1024, sform code 2, qform code 1\n");
    EXPECT_EQ(run.err,
              "gvr: warning: a.nii.gz: 3 samples were clamped into int16's range (pass --float32 to keep them)\n");
}

TEST(VolumeOutputOptions, SaysWhyANiftiIsFloat32) {
    NiftiStorage storage;
    storage.float32Reason = "the source is float64";
    const Printed run = printed({{"b.nii", VolumeFileFormat::Nifti, 512, 0}}, storage);
    // Unit scaling is not worth a mention.
    EXPECT_EQ(run.out, "wrote b.nii (512 B): NIfTI, float32, sform code 1, qform code 1\n");
    EXPECT_EQ(run.err, "gvr: warning: b.nii is float32: the source is float64\n");
}

}  // namespace
}  // namespace gvr
