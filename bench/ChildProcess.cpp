#include "bench/ChildProcess.h"

#include "pipeline/Error.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

namespace gvr {

namespace {

/// Runs in the forked child: only async-signal-safe calls until exec.
[[noreturn]] void becomeChild(char* const* argv, int stdoutFd, int logFd, pid_t parent, bool ownGroup) {
    if (ownGroup) setpgid(0, 0);  // so that a time-out reaches any programs it starts
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    dup2(stdoutFd, STDOUT_FILENO);
    dup2(logFd, STDERR_FILENO);
    execv(argv[0], argv);
    _exit(127);
}

using Clock = std::chrono::steady_clock;

/// Milliseconds left until @a deadline for poll(), -1 (wait for ever) without one.
int millisecondsLeft(const std::optional<Clock::time_point>& deadline) {
    if (!deadline) return -1;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(*deadline - Clock::now()).count();
    return int(std::clamp<long long>(left, 0, 1000));
}

bool passed(const std::optional<Clock::time_point>& deadline) { return deadline && Clock::now() >= *deadline; }

/// Everything written to @a fd until its writer closes it; false when @a deadline passed first.
bool readAll(int fd, const std::optional<Clock::time_point>& deadline, std::string& text) {
    char buffer[65536];
    for (;;) {
        if (passed(deadline)) return false;
        pollfd ready{fd, POLLIN, 0};
        const int polled = poll(&ready, 1, millisecondsLeft(deadline));
        if (polled < 0 && errno != EINTR) return true;
        if (polled <= 0) continue;
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n > 0) {
            text.append(buffer, std::size_t(n));
        } else if (n == 0 || errno != EINTR) {
            return true;
        }
    }
}

/// Waits for @a pid to end; false when @a deadline passed first (a child may close
/// its output and still run on).
bool waitFor(pid_t pid, const std::optional<Clock::time_point>& deadline, int& status, rusage& usage) {
    for (;;) {
        const pid_t ended = wait4(pid, &status, deadline ? WNOHANG : 0, &usage);
        if (ended == pid) return true;
        if (ended < 0 && errno != EINTR) return true;
        if (passed(deadline)) return false;
        if (deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

std::string lastNonEmptyLine(const std::string& path, std::streamoff from) {
    std::ifstream in(path);
    in.seekg(from);
    std::string line, last;
    while (std::getline(in, line)) {
        const auto end = line.find_last_not_of(" \r\t");
        // Progress bars redraw with '\r'; the message that matters follows the last one.
        const auto redraw = line.find_last_of('\r', end == std::string::npos ? 0 : end);
        const std::size_t begin = redraw == std::string::npos ? 0 : redraw + 1;
        const std::string text = end == std::string::npos ? "" : line.substr(begin, end + 1 - begin);
        // CLI11 follows a parse error with this hint; the error itself is more use.
        if (!text.empty() && text != "Run with --help for more information.") last = text;
    }
    return last;
}

}  // namespace

ChildResult runChild(const std::vector<std::string>& argv, const std::string& logPath, double timeoutSeconds) {
    std::vector<char*> cArgs;
    for (const std::string& a : argv) cArgs.push_back(const_cast<char*>(a.c_str()));
    cArgs.push_back(nullptr);
    const int logFd = open(logPath.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (logFd < 0) throw InputError(logPath, "cannot open the log for writing");
    const std::streamoff logStart = lseek(logFd, 0, SEEK_END);
    int pipeFds[2];
    if (pipe2(pipeFds, O_CLOEXEC) != 0) {
        close(logFd);
        throw std::runtime_error("cannot create a pipe for " + argv[0]);
    }
    const auto start = Clock::now();
    std::optional<Clock::time_point> deadline;
    if (timeoutSeconds > 0) deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeoutSeconds));
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) becomeChild(cArgs.data(), pipeFds[1], logFd, parent, deadline.has_value());
    if (pid > 0 && deadline) setpgid(pid, pid);  // as the child does: whichever runs first
    close(pipeFds[1]);
    close(logFd);
    if (pid < 0) {
        close(pipeFds[0]);
        throw std::runtime_error("cannot start " + argv[0]);
    }
    ChildResult result;
    int status = 0;
    rusage usage{};
    result.timedOut = !readAll(pipeFds[0], deadline, result.output) || !waitFor(pid, deadline, status, usage);
    close(pipeFds[0]);
    if (result.timedOut) {
        kill(-pid, SIGKILL);
        kill(pid, SIGKILL);  // in case it left the group
        while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
        }
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.peakRssMiB = usage.ru_maxrss / 1024.0;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.lastError = lastNonEmptyLine(logPath, logStart);
    return result;
}

std::string currentExecutable() {
    return std::filesystem::read_symlink("/proc/self/exe").string();
}

}  // namespace gvr
