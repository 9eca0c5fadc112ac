// Running a child program for the batch benchmark: its exit code or signal, its
// output kept and its last error line, stderr appended to the log, and the time limit.

#include "bench/ChildProcess.h"
#include "tests/TestHelpers.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

using namespace gvr;

namespace {

TEST(ChildProcess, KeepsOutputTheLastErrorLineAndTheExitCode) {
    test::TempDir dir;
    const std::string log = dir.path("log");
    const ChildResult result =
        runChild({"/bin/sh", "-c", "echo out; echo first >&2; echo last >&2; echo >&2; exit 3"}, log);
    EXPECT_EQ(result.exitCode, 3);
    EXPECT_FALSE(result.ok());
    EXPECT_FALSE(result.timedOut);
    EXPECT_EQ(result.output, "out\n");
    EXPECT_EQ(result.lastError, "last");  // the last line that is not empty
    const std::string logged = test::readBytes(log);
    EXPECT_NE(logged.find("first\nlast\n"), std::string::npos) << logged;

    runChild({"/bin/sh", "-c", "echo again >&2"}, log);
    EXPECT_NE(test::readBytes(log).find("first"), std::string::npos) << "the log is appended to, not replaced";
}

TEST(ChildProcess, TheLastErrorIsWhatFollowsTheLastProgressRedraw) {
    test::TempDir dir;
    const ChildResult result = runChild(
        {"/bin/sh", "-c", "printf 'fitting 10%%\\rfitting 90%%\\rout of memory   \\n' >&2; exit 1"}, dir.path("log"));
    EXPECT_EQ(result.lastError, "out of memory");
}

TEST(ChildProcess, ASignalIsReportedAs128PlusItsNumber) {
    test::TempDir dir;
    const ChildResult result = runChild({"/bin/sh", "-c", "kill -TERM $$"}, dir.path("log"));
    EXPECT_EQ(result.exitCode, 128 + 15);
    EXPECT_FALSE(result.timedOut);
}

TEST(ChildProcess, CurrentExecutableIsThisTestProgram) {
    const std::filesystem::path self = currentExecutable();
    EXPECT_TRUE(std::filesystem::exists(self)) << self;
    EXPECT_EQ(self.filename(), "gvr_tests");
}

/// Whether process @a pid has ended (gone, or a zombie waiting for its reaper).
bool ended(const std::string& pid) {
    std::ifstream stat("/proc/" + pid + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return true;
    return line.find(") Z") != std::string::npos;
}

TEST(ChildProcess, ATimeLimitKillsTheChildAndItsChildren) {
    test::TempDir dir;
    const auto start = std::chrono::steady_clock::now();
    const std::string pidFile = dir.path("background.pid");
    const ChildResult result = runChild(
        {"/bin/sh", "-c", "sleep 30 & echo $! > '" + pidFile + "'; sleep 30; echo never"}, dir.path("log"), 0.5);
    EXPECT_TRUE(result.timedOut);
    EXPECT_FALSE(result.ok());
    EXPECT_EQ(result.output, "");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
    const std::string background = test::readBytes(pidFile).substr(0, test::readBytes(pidFile).find('\n'));
    ASSERT_FALSE(background.empty());
    for (int tries = 0; tries < 200 && !ended(background); ++tries) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(ended(background)) << "the time limit left process " << background << " running";

    const ChildResult quick = runChild({"/bin/sh", "-c", "echo done"}, dir.path("log"), 10);
    EXPECT_FALSE(quick.timedOut);
    EXPECT_TRUE(quick.ok());
    EXPECT_EQ(quick.output, "done\n");
}

// A codec that left a background process held the row to its time limit, through
// the output it inherited, and left the process running.
TEST(ChildProcess, ARunEndsWithTheChildAndTakesWhatItLeftRunningWithIt) {
    test::TempDir dir;
    const auto start = std::chrono::steady_clock::now();
    const ChildResult result = runChild({"/bin/sh", "-c", "sleep 30 & echo $!"}, dir.path("log"), 20.0);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
    EXPECT_FALSE(result.timedOut);
    EXPECT_TRUE(result.ok());
    const std::string daemon = result.output.substr(0, result.output.find('\n'));
    ASSERT_FALSE(daemon.empty());
    for (int tries = 0; tries < 200 && !ended(daemon); ++tries)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(ended(daemon)) << "process " << daemon << " outlived the run";
}

TEST(ChildProcess, TheChildGetsNoDescriptorButItsOwnThree) {
    test::TempDir dir;
    const int open = ::open(dir.path("log").c_str(), O_WRONLY | O_CREAT, 0644);  // not close-on-exec
    ASSERT_GE(open, 0);
    ASSERT_EQ(dup2(open, 57), 57);
    const ChildResult result = runChild({"/bin/sh", "-c", "ls /proc/$$/fd; cat"}, dir.path("log"), 10.0);
    close(57);
    close(open);
    EXPECT_TRUE(result.ok());
    EXPECT_FALSE(result.timedOut) << "cat read this process's standard input";
    std::istringstream lines(result.output);
    for (std::string fd; std::getline(lines, fd);) EXPECT_LE(std::stoi(fd), 2) << "inherited descriptor " << fd;
}

// A codec that flooded its output grew gvr to gigabytes.
TEST(ChildProcess, WhatIsKeptOfTheOutputIsCapped) {
    test::TempDir dir;
    const ChildResult result = runChild({"/bin/sh", "-c", "head -c 50000000 /dev/zero"}, dir.path("log"), 60.0);
    EXPECT_TRUE(result.ok());
    EXPECT_EQ(result.output.size(), std::size_t(16) << 20);
}

}  // namespace
