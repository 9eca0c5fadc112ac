// gvr's own stderr: settings named as flags, C and C++ output in order on one
// descriptor, and library output held back, then shown line by line with a prefix.

#include "cli/Diagnostics.h"
#include "tests/TestHelpers.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <string>

namespace gvr {
namespace {

/// What reaches descriptor @a fd while @a run runs.
std::string writtenTo(int fd, const std::function<void()>& run) {
    test::TempDir dir;
    const std::string path = dir.path("caught");
    std::fflush(diagnosticsFile());
    const int saved = dup(fd);
    const int file = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(file, fd);
    close(file);
    run();
    std::fflush(diagnosticsFile());
    dup2(saved, fd);
    close(saved);
    return test::readBytes(path);
}

TEST(Diagnostics, SettingsInLibraryMessagesBecomeFlags) {
    EXPECT_EQ(inCommandLineTerms("scan.nii: pass `nan_to=VALUE` to replace them"),
              "scan.nii: pass --nan-to VALUE to replace them");
    EXPECT_EQ(inCommandLineTerms("`reuse_angle` must lie in [0, 60]"), "--reuse-angle must lie in [0, 60]");
    EXPECT_EQ(inCommandLineTerms("`lr` must be positive"), "--lr must be positive");
    // A file name in backquotes is the user's, not a setting.
    EXPECT_EQ(inCommandLineTerms("`My Scan`.nii: `volume=3` is out of range"),
              "`My Scan`.nii: --volume 3 is out of range");
    EXPECT_EQ(inCommandLineTerms("no settings here"), "no settings here");
}

TEST(Diagnostics, StreamAndFileShareOneDescriptorInOrder) {
    const std::string written = writtenTo(diagnosticsFd(), [] {
        diagnostics() << "gvr: warning: " << 42 << "\n";
        std::fputs("progress\n", diagnosticsFile());
        diagnostics() << "gvr: error: last\n";
    });
    EXPECT_EQ(written, "gvr: warning: 42\nprogress\ngvr: error: last\n");
}

TEST(Diagnostics, LibraryOutputIsHeldBackThenShownLineByLine) {
    if (diagnosticsFd() != STDERR_FILENO) GTEST_SKIP() << "stderr was diverted earlier in this process";
    EXPECT_EQ(diagnosticsFile(), stderr);
    const int userStderr = dup(STDERR_FILENO);
    divertLibraryOutput();
    const int own = diagnosticsFd();
    EXPECT_NE(own, STDERR_FILENO) << "no scratch file to divert library output into";
    divertLibraryOutput();  // once only: a second call must not lose the first capture
    EXPECT_EQ(diagnosticsFd(), own);

    // As libpng or nifticlib would write: straight to descriptor 2.
    const std::string library = "libpng warning: iCCP: known incorrect sRGB profile\n\nnifti: bad dim\nlast words";
    EXPECT_EQ(write(STDERR_FILENO, library.data(), library.size()), ssize_t(library.size()));
    const std::string shown = writtenTo(own, [] { showLibraryOutput(); });

    dup2(userStderr, STDERR_FILENO);  // leave the rest of this process's stderr as it was
    close(userStderr);
    EXPECT_EQ(shown,
              "gvr: library: libpng warning: iCCP: known incorrect sRGB profile\n"
              "gvr: library: nifti: bad dim\n"
              "gvr: library: last words\n");
}

}  // namespace
}  // namespace gvr
