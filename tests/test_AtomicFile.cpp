// Fault injection for every writer: a file size limit (what a full disk looks like
// to a writer) and SIGTERM in the middle of a write. The existing output must
// survive and no temporary file may be left. Each fault runs in a child process
// (a death test), so that the limit and the signal do not reach the test runner.

#include "io/Ingest.h"
#include "io/formats/GridFile.h"
#include "io/formats/NiftiWriter.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <cstring>
#include <fstream>
#include <random>

namespace gvr {
namespace {

constexpr int kRefused = 3;  // the child's exit code when the writer threw InputError

/// Entries in @a dir whose names start with ".gvr-": what an interrupted write leaves.
std::vector<std::string> temporaries(const test::DeathTestDir& dir) {
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::directory_iterator(dir.root())) {
        if (entry.path().filename().string().rfind(".gvr-", 0) == 0) found.push_back(entry.path().string());
    }
    return found;
}

/// A writer of @a text at the path it is given.
std::function<void(const std::string&)> writeText(const std::string& text) {
    return [text](const std::string& path) { std::ofstream(path) << text; };
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
    test::DeathTestDir mDir;
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
    EXPECT_EXIT(writeUnderAFileSizeLimit([&] { writeNifti(nifti, volume); }), ::testing::ExitedWithCode(kRefused), "");
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
    const auto fail = [](const std::string&) { throw InputError("out.nii.gz", "cannot write (disk full?)"); };
    EXPECT_THROW(writeAllOrNone({mExisting, second}, {writeText("new grid"), fail}), InputError);
    expectExistingOutputIntact();
    EXPECT_EQ(test::readBytes(second), "the previous NIfTI");
    writeAllOrNone({mExisting, second}, {writeText("new grid"), writeText("new NIfTI")});
    EXPECT_EQ(test::readBytes(mExisting), "new grid");
    EXPECT_EQ(test::readBytes(second), "new NIfTI");
    EXPECT_TRUE(temporaries(mDir).empty());
}

TEST_F(AtomicFile, TheTemporaryLiesInAFolderThatOnlyThisWriteMade) {
    // The temporary's name was ".tmp<pid>-out.vdb" beside the output: a link planted
    // at it sent the write into the link's target.
    const std::string victim = mDir.path("victim.txt");
    test::writeBytes(victim, "a user's file");
    std::filesystem::create_symlink(victim, mDir.path(".tmp" + std::to_string(getpid()) + "-out.vdb"));
    std::string temporary;
    writeAtomically(mExisting, [&](const std::string& path) {
        temporary = path;
        std::ofstream(path) << "the new output";
    });
    EXPECT_EQ(test::readBytes(mExisting), "the new output");
    EXPECT_EQ(test::readBytes(victim), "a user's file");
    const std::filesystem::path folder = std::filesystem::path(temporary).parent_path();
    EXPECT_EQ(folder.parent_path(), std::filesystem::path(mExisting).parent_path());
    EXPECT_EQ(folder.filename().string().rfind(".gvr-" + std::to_string(getpid()) + "-", 0), 0u) << temporary;
    EXPECT_EQ(std::filesystem::path(temporary).filename(), "out.vdb");  // writers choose a format by extension
    EXPECT_TRUE(temporaries(mDir).empty());
}

TEST_F(AtomicFile, OnlyStagingFoldersOfGoneProcessesAreCleared) {
    namespace fs = std::filesystem;
    const auto folder = [&](const std::string& name, fs::perms perms) {
        fs::create_directory(mDir.path(name));
        test::writeBytes(mDir.path(name) + "/out.vdb", "staged");
        fs::permissions(mDir.path(name), perms);
        return mDir.path(name);
    };
    const std::string stale = folder(".gvr-999999999-Ab3xYz", fs::perms::owner_all);  // no pid runs that high
    const std::string live = folder(".gvr-1-Ab3xYz", fs::perms::owner_all);           // init runs
    // Inputs that only look like temporaries: an earlier gvr's name, and a shared folder.
    const std::string lookalike = mDir.path(".tmp999999999-all-x.nii.gz");
    test::writeBytes(lookalike, "an input");
    const std::string shared = folder(".gvr-999999999-Cd4xYz", fs::perms::owner_all | fs::perms::group_read);
    writeAtomically(mExisting, writeText("new"));
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(lookalike));
    EXPECT_TRUE(fs::exists(shared));
}

TEST_F(AtomicFile, ARenameThatFailsGivesTheOutputsAlreadyRenamedTheirOldFiles) {
    // The first output was renamed over the user's older file, then the second
    // rename failed: exit 2, with the first already replaced.
    const std::string second = mDir.path("out.nii.gz");
    const auto stageThenBlockTheRename = [&](const std::string& path) {
        std::ofstream(path) << "new NIfTI";
        std::filesystem::create_directories(second + "/in the way");  // rename(2) refuses a full folder
    };
    EXPECT_THROW(writeAllOrNone({mExisting, second}, {writeText("new grid"), stageThenBlockTheRename}), InputError);
    expectExistingOutputIntact();
    const std::string fresh = mDir.path("fresh.vdb");  // no older file: the rename is undone by removing it
    std::filesystem::remove_all(second);
    EXPECT_THROW(writeAllOrNone({fresh, second}, {writeText("new grid"), stageThenBlockTheRename}), InputError);
    EXPECT_FALSE(std::filesystem::exists(fresh));
    EXPECT_TRUE(temporaries(mDir).empty());
}

TEST_F(AtomicFile, ASignalWhileTheSecondOutputIsWrittenLeavesNoStagedFile) {
    // The first output, staged and complete, was left behind (50 MB in the probe).
    const std::string second = mDir.path("out.nii.gz");
    const auto writeBothThenGetKilled = [&] {
        removeTemporariesOnSignals();
        const auto halfThenKilled = [](const std::string& path) {
            writeAtomically(path, [](const std::string& temporary) {  // a writer that stages on its own
                std::ofstream(temporary) << "half of a NIfTI";
                std::raise(SIGTERM);
            });
        };
        writeAllOrNone({mExisting, second}, {writeText("new grid"), halfThenKilled});
    };
    EXPECT_EXIT(writeBothThenGetKilled(), ::testing::KilledBySignal(SIGTERM), "");
    expectExistingOutputIntact();
    EXPECT_FALSE(std::filesystem::exists(second));
}

TEST_F(AtomicFile, WhatSigkillLeavesIsClearedByTheNextWriteIntoTheFolder) {
    // A nested writer's temporary, named after the staged file and the dead pid,
    // matched no later write's name and stayed.
    const auto writeBothThenGetKilled = [&] {
        const auto halfThenKilled = [](const std::string& path) {
            writeAtomically(path, [](const std::string& temporary) {
                std::ofstream(temporary) << "half of a NIfTI";
                std::raise(SIGKILL);
            });
        };
        writeAllOrNone({mExisting, mDir.path("out.nii.gz")}, {writeText("new grid"), halfThenKilled});
    };
    EXPECT_EXIT(writeBothThenGetKilled(), ::testing::KilledBySignal(SIGKILL), "");
    EXPECT_FALSE(temporaries(mDir).empty());
    writeAtomically(mDir.path("other.vdb"), writeText("another output"));
    expectExistingOutputIntact();
}

}  // namespace
}  // namespace gvr
