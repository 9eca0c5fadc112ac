#include "ChildProcess.h"

#include "Error.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>

namespace gvr {

namespace {

/// Runs in the forked child: only async-signal-safe calls until exec.
[[noreturn]] void becomeChild(char* const* argv, int stdoutFd, int logFd, pid_t parent) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died before prctl took effect
    dup2(stdoutFd, STDOUT_FILENO);
    dup2(logFd, STDERR_FILENO);
    execv(argv[0], argv);
    _exit(127);
}

std::string readAll(int fd) {
    std::string text;
    char buffer[65536];
    for (;;) {
        const ssize_t n = read(fd, buffer, sizeof buffer);
        if (n > 0) {
            text.append(buffer, std::size_t(n));
        } else if (n == 0 || errno != EINTR) {
            return text;
        }
    }
}

std::string lastNonEmptyLine(const std::string& path, std::streamoff from) {
    std::ifstream in(path);
    in.seekg(from);
    std::string line, last;
    while (std::getline(in, line)) {
        const auto end = line.find_last_not_of(" \r\t");
        // Progress bars redraw with '\r'; the message that matters follows the last one.
        const auto start = line.find_last_of('\r', end == std::string::npos ? 0 : end);
        const std::string text = end == std::string::npos ? "" : line.substr(start == std::string::npos ? 0 : start + 1, end + 1);
        // CLI11 follows a parse error with this hint; the error itself is more use.
        if (!text.empty() && text != "Run with --help for more information.") last = text;
    }
    return last;
}

}  // namespace

ChildResult runChild(const std::vector<std::string>& argv, const std::string& logPath) {
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
    const auto start = std::chrono::steady_clock::now();
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) becomeChild(cArgs.data(), pipeFds[1], logFd, parent);
    close(pipeFds[1]);
    close(logFd);
    if (pid < 0) {
        close(pipeFds[0]);
        throw std::runtime_error("cannot start " + argv[0]);
    }
    ChildResult result;
    result.output = readAll(pipeFds[0]);
    close(pipeFds[0]);
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.peakRssMiB = usage.ru_maxrss / 1024.0;
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.lastError = lastNonEmptyLine(logPath, logStart);
    return result;
}

std::string currentExecutable() {
    return std::filesystem::read_symlink("/proc/self/exe").string();
}

}  // namespace gvr
