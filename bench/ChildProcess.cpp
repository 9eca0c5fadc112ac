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

/// The most of a child's standard output kept: gvr's own steps print a few
/// kilobytes of JSON, and a codec that flooded its output grew gvr's memory with it.
constexpr std::size_t kMostOutputBytes = 16u << 20;

/// Closes every descriptor above stderr. A codec inherited gvr's (a copy of its
/// stderr among them), so a program it left running held them open.
void closeInheritedDescriptors() {
    if (close_range(3, ~0u, 0) == 0) return;
    const long most = std::min(sysconf(_SC_OPEN_MAX), 65536L);  // kernels before 5.9 lack close_range
    for (int fd = 3; fd < most; ++fd) close(fd);
}

/// Runs in the forked child: only async-signal-safe calls until exec.
[[noreturn]] void becomeChild(char* const* argv, int stdinFd, int stdoutFd, int logFd, pid_t parent, bool ownGroup) {
    if (ownGroup) setpgid(0, 0);  // so that a time-out reaches any programs it starts
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    dup2(stdinFd, STDIN_FILENO);
    dup2(stdoutFd, STDOUT_FILENO);
    dup2(logFd, STDERR_FILENO);
    closeInheritedDescriptors();
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

/// Appends what @a fd holds now to @a text, up to kMostOutputBytes (the rest is
/// read and dropped); false once its writers have all closed it.
bool readAvailable(int fd, std::string& text) {
    char buffer[65536];
    for (;;) {
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n > 0) {
            text.append(buffer, std::min(std::size_t(n), kMostOutputBytes - std::min(text.size(), kMostOutputBytes)));
        } else if (n == 0) {
            return false;
        } else if (errno != EINTR) {
            return errno == EAGAIN || errno == EWOULDBLOCK;
        }
    }
}

/// Whether @a pid has ended, left unreaped so that its process group stays its own.
bool hasEnded(pid_t pid) {
    siginfo_t info{};
    return waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid;
}

/// Collects @a pid's standard output from @a fd until it ends; false when @a deadline
/// passed first. Only the child itself is waited for: a program it left running
/// may hold the output open for ever.
bool collectUntilEnded(pid_t pid, int fd, const std::optional<Clock::time_point>& deadline, std::string& output) {
    bool open = true;
    for (;;) {
        if (hasEnded(pid)) {
            if (open) readAvailable(fd, output);
            return true;
        }
        if (passed(deadline)) return false;
        pollfd ready{fd, POLLIN, 0};
        const int waitMs = std::min(open ? 100 : 10, deadline ? millisecondsLeft(deadline) : 100);
        if (!open || poll(&ready, 1, waitMs) <= 0) {
            if (!open) std::this_thread::sleep_for(std::chrono::milliseconds(waitMs));
            continue;
        }
        open = readAvailable(fd, output);
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
    const int logFd = open(logPath.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (logFd < 0) throw InputError(logPath, "cannot open the log for writing");
    const std::streamoff logStart = lseek(logFd, 0, SEEK_END);
    const int nullFd = open("/dev/null", O_RDONLY | O_CLOEXEC);  // no step reads gvr's standard input
    int pipeFds[2];
    if (nullFd < 0 || pipe2(pipeFds, O_CLOEXEC) != 0) {
        close(logFd);
        if (nullFd >= 0) close(nullFd);
        throw std::runtime_error("cannot create a pipe for " + argv[0]);
    }
    fcntl(pipeFds[0], F_SETFL, O_NONBLOCK);
    const auto start = Clock::now();
    std::optional<Clock::time_point> deadline;
    if (timeoutSeconds > 0)
        deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeoutSeconds));
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) becomeChild(cArgs.data(), nullFd, pipeFds[1], logFd, parent, deadline.has_value());
    if (pid > 0 && deadline) setpgid(pid, pid);  // as the child does: whichever runs first
    close(pipeFds[1]);
    close(logFd);
    close(nullFd);
    if (pid < 0) {
        close(pipeFds[0]);
        throw std::runtime_error("cannot start " + argv[0]);
    }
    ChildResult result;
    result.timedOut = !collectUntilEnded(pid, pipeFds[0], deadline, result.output);
    close(pipeFds[0]);
    // A program of its own group that a step left running (a daemon) goes with it;
    // the leader, not yet reaped, keeps the group's id from being reused.
    if (deadline) kill(-pid, SIGKILL);
    if (result.timedOut) kill(pid, SIGKILL);  // in case it left the group
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.peakRssMiB = usage.ru_maxrss / 1024.0;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.lastError = lastNonEmptyLine(logPath, logStart);
    return result;
}

std::string currentExecutable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

}  // namespace gvr
