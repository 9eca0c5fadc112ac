// Fault injection for every writer: a file size limit (what a full disk looks like
// to a writer) and SIGTERM in the middle of a write. The existing output must
// survive and no temporary file may be left. Each fault runs in a child process
// (a death test), so that the limit and the signal do not reach the test runner.

#include "io/AtomicFile.h"
#include "io/GridFile.h"
#include "io/Ingest.h"
#include "io/NiftiWriter.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <sys/resource.h>

#include <csignal>
#include <cstring>
#include <fstream>
#include <random>

namespace gvr {
namespace {

constexpr int kRefused = 3;  // the child's exit code when the writer threw InputError

/// Files in @a dir whose names start with ".tmp": what an interrupted write leaves.
std::vector<std::string> temporaries(const test::TempDir& dir) {
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::directory_iterator(dir.root())) {
        if (entry.path().filename().string().rfind(".tmp", 0) == 0) found.push_back(entry.path().string());
    }
    return found;
}

/// In a child: limits files to 64 KiB, runs @a write, and exits kRefused if it
/// threw InputError, 0 if it claimed success.
void writeUnderAFileSizeLimit(const std::function<void()>& write) {
    removeTemporariesOnSignals();  // as the gvr command does
    rlimit limit{64 * 1024, 64 * 1024};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
        write();
    } catch (const InputError&) {
        std::_Exit(kRefused);
    }
    std::_Exit(0);
}

class AtomicFile : public ::testing::Test {
protected:
    void SetUp() override {
        GTEST_FLAG_SET(death_test_style, "threadsafe");
        test::writeBytes(mExisting, "the previous output");
    }
    void expectExistingOutputIntact() {
        EXPECT_EQ(test::readBytes(mExisting), "the previous output");
        EXPECT_TRUE(temporaries(mDir).empty()) << temporaries(mDir).front();
    }
    test::TempDir mDir;
    const std::string mExisting = mDir.path("out.vdb");
};

TEST_F(AtomicFile, AFullDiskFailsTheGridWriterAndKeepsTheOldFile) {
    GVR_REQUIRE_SHARED_DATA();
    const IngestResult ch2 = ingest(test::sharedData("mri-colin27-aal/ch2.nii.gz"), {});  // about 6 MiB as VDB
    EXPECT_EXIT(writeUnderAFileSizeLimit([&] { writeGridFile(mExisting, {ch2.grid}); }),
                ::testing::ExitedWithCode(kRefused), "");
    expectExistingOutputIntact();
}

TEST_F(AtomicFile, AFullDiskFailsTheNiftiWriterAndKeepsTheOldFile) {
    FloatVolume volume(openvdb::Coord(64, 64, 64), 1);  // 1 MiB of random float32: no gzip gets it below 64 KiB
    std::mt19937 random(7);
    std::uniform_real_distribution<float> value(0.0f, 1000.0f);
    for (float& v : volume.values) v = value(random);
    const std::string nifti = mDir.path("out.nii.gz");
    test::writeBytes(nifti, "the previous output");
    EXPECT_EXIT(writeUnderAFileSizeLimit([&] { writeNifti(nifti, volume); }), ::testing::ExitedWithCode(kRefused),
                "");
    EXPECT_EQ(test::readBytes(nifti), "the previous output");
    EXPECT_TRUE(temporaries(mDir).empty());
}

TEST_F(AtomicFile, AnyTerminatingSignalDuringAWriteRemovesTheTemporaryAndKeepsTheOldFile) {
    // SIGQUIT, SIGUSR1 and SIGALRM once left their temporaries behind.
    for (const int signal : {SIGTERM, SIGINT, SIGHUP, SIGQUIT, SIGUSR1, SIGALRM, SIGPIPE}) {
        const auto writeHalfThenGetKilled = [&] {
            removeTemporariesOnSignals();
            writeAtomically(mExisting, [signal](const std::string& temporary) {
                std::ofstream(temporary) << "half of a new output";
                std::raise(signal);
            });
        };
        EXPECT_EXIT(writeHalfThenGetKilled(), ::testing::KilledBySignal(signal), "") << strsignal(signal);
        expectExistingOutputIntact();
    }
}

TEST_F(AtomicFile, SeveralOutputsAreWrittenAllOrNone) {
    // When the second of two outputs failed, the first, already renamed over the
    // user's older file, was deleted: both files were lost.
    const std::string second = mDir.path("out.nii.gz");
    test::writeBytes(second, "the previous NIfTI");
    const auto writeText = [](const std::string& text) {
        return [text](const std::string& path) { std::ofstream(path) << text; };
    };
    const auto fail = [](const std::string&) { throw InputError("out.nii.gz", "cannot write (disk full?)"); };
    EXPECT_THROW(writeAllOrNone({mExisting, second}, {writeText("new grid"), fail}), InputError);
    expectExistingOutputIntact();
    EXPECT_EQ(test::readBytes(second), "the previous NIfTI");
    writeAllOrNone({mExisting, second}, {writeText("new grid"), writeText("new NIfTI")});
    EXPECT_EQ(test::readBytes(mExisting), "new grid");
    EXPECT_EQ(test::readBytes(second), "new NIfTI");
    EXPECT_TRUE(temporaries(mDir).empty());
}

}  // namespace
}  // namespace gvr
