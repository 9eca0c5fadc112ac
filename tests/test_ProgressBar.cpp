// The progress bar on gvr's stderr: nothing unless that is a terminal and the bar is
// enabled; on a terminal, one redrawn line that is ended when the bar goes. A
// pseudo-terminal stands in for the user's, so what is drawn can be read back.
// Times and throttled redraws are not asserted: only what is drawn regardless of them.

#include "cli/Diagnostics.h"
#include "cli/ProgressBar.h"
#include "tests/TestHelpers.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace gvr {
namespace {

/// A pseudo-terminal in place of gvr's stderr while it lives.
class FakeTerminal {
public:
    FakeTerminal() {
        mMaster = posix_openpt(O_RDWR | O_NOCTTY);
        if (mMaster < 0 || grantpt(mMaster) != 0 || unlockpt(mMaster) != 0) return;
        const char* name = ptsname(mMaster);
        if (!name) return;
        mSlave = open(name, O_RDWR | O_NOCTTY);
        if (mSlave < 0) return;
        termios settings{};
        if (tcgetattr(mSlave, &settings) == 0) {
            settings.c_oflag &= ~tcflag_t(OPOST);  // "\n" arrives as written, not as "\r\n"
            tcsetattr(mSlave, TCSANOW, &settings);
        }
        std::fflush(diagnosticsFile());
        mSaved = dup(diagnosticsFd());
        if (mSaved >= 0 && dup2(mSlave, diagnosticsFd()) < 0) {
            close(mSaved);
            mSaved = -1;
        }
    }
    ~FakeTerminal() {
        if (mSaved >= 0) {
            dup2(mSaved, diagnosticsFd());
            close(mSaved);
        }
        if (mSlave >= 0) close(mSlave);
        if (mMaster >= 0) close(mMaster);
    }
    FakeTerminal(const FakeTerminal&) = delete;
    FakeTerminal& operator=(const FakeTerminal&) = delete;

    bool ready() const { return mSaved >= 0; }

    /// What the terminal received up to the first line end.
    std::string readLine() {
        std::string text;
        char buffer[4096];
        while (text.find('\n') == std::string::npos) {
            pollfd master{mMaster, POLLIN, 0};
            if (poll(&master, 1, 10000) <= 0) break;  // a guard against hanging, not a timing
            const ssize_t n = read(mMaster, buffer, sizeof buffer);
            if (n <= 0) break;
            text.append(buffer, std::size_t(n));
        }
        return text;
    }

private:
    int mMaster = -1, mSlave = -1, mSaved = -1;
};

bool endsWith(const std::string& text, const std::string& end) {
    return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

TEST(ProgressBar, OffATerminalItWritesNothing) {
    test::TempDir dir;
    const std::string path = dir.path("stderr");
    std::fflush(diagnosticsFile());
    const int saved = dup(diagnosticsFd());
    const int file = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(file, diagnosticsFd());
    close(file);
    {
        ProgressBar bar("reading");
        bar.update(0.5, "half");
        bar.callback()(1.0);
    }
    std::fflush(diagnosticsFile());
    dup2(saved, diagnosticsFd());
    close(saved);
    EXPECT_EQ(test::readBytes(path), "");  // a log file or a pipe gets no carriage returns
}

TEST(ProgressBar, DisabledItWritesNothingEvenOnATerminal) {
    FakeTerminal terminal;
    if (!terminal.ready()) GTEST_SKIP() << "no pseudo-terminal";
    {
        ProgressBar bar("reading", /*enabled=*/false);
        bar.update(0.5, "half");
        bar.callback()(1.0);
    }
    std::fputs("end\n", diagnosticsFile());  // the first thing the terminal receives
    EXPECT_EQ(terminal.readLine(), "end\n");
}

TEST(ProgressBar, OnATerminalItDrawsTheLabelBarPercentAndDetailAndEndsTheLine) {
    FakeTerminal terminal;
    if (!terminal.ready()) GTEST_SKIP() << "no pseudo-terminal";
    {
        ProgressBar bar("reading");
        bar.update(0.5, "iteration 120");
    }
    const std::string drawn = terminal.readLine();
    // The label padded to 14 columns, then 15 of 30 cells filled.
    const std::string start =
        "\rreading" + std::string(8, ' ') + "[" + std::string(15, '#') + std::string(15, ' ') + "]  50.0 %  ";
    EXPECT_EQ(drawn.rfind(start, 0), 0u) << drawn;
    EXPECT_NE(drawn.find(" s elapsed, ETA "), std::string::npos) << drawn;
    // Erases what a longer earlier line left, then the line ends as the bar goes.
    EXPECT_TRUE(endsWith(drawn, " s  iteration 120\033[K\n")) << drawn;
}

TEST(ProgressBar, FractionsAreClampedAndTheEndIsAlwaysDrawn) {
    FakeTerminal terminal;
    if (!terminal.ready()) GTEST_SKIP() << "no pseudo-terminal";
    {
        ProgressBar bar("fitting");
        bar.update(-1.0, "start");  // the first update is always drawn
        bar.callback()(2.0);        // the end is drawn however soon it follows
    }
    const std::string drawn = terminal.readLine();
    const std::size_t second = drawn.find('\r', 1);
    ASSERT_NE(second, std::string::npos) << drawn;
    const std::string first = drawn.substr(0, second), last = drawn.substr(second);
    EXPECT_EQ(first.rfind("\rfitting" + std::string(8, ' ') + "[" + std::string(30, ' ') + "]   0.0 %  ", 0), 0u)
        << first;
    EXPECT_TRUE(endsWith(first, "ETA    0.0 s  start\033[K")) << first;
    EXPECT_EQ(last.rfind("\rfitting" + std::string(8, ' ') + "[" + std::string(30, '#') + "] 100.0 %  ", 0), 0u)
        << last;
    EXPECT_TRUE(endsWith(last, "ETA    0.0 s  \033[K\n")) << last;  // the callback gives no detail
}

}  // namespace
}  // namespace gvr
