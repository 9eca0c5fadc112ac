#include "AtomicFile.h"

#include "Error.h"

#include <unistd.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

namespace gvr {

namespace {

namespace fs = std::filesystem;

/// The temporary file being written, for the signal handler: plain bytes, since a
/// handler may only call async-signal-safe functions such as unlink.
char gTemporary[4096];
volatile std::sig_atomic_t gHasTemporary = 0;
std::mutex gWriting;  // one atomic write at a time, so one slot is enough

extern "C" void removeTemporaryAndExit(int signal) {
    if (gHasTemporary) unlink(gTemporary);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

bool sameFile(const fs::path& a, const fs::path& b) {
    std::error_code error;
    if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
    return fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
}

}  // namespace

void removeTemporariesOnSignals() {
    static std::once_flag installed;
    std::call_once(installed, [] {
        for (int signal : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction action {};
            action.sa_handler = removeTemporaryAndExit;
            sigemptyset(&action.sa_mask);
            sigaction(signal, &action, nullptr);
        }
        // Past ulimit -f the kernel would kill the process and leave the temporary
        // behind; ignored, the write fails with EFBIG and the writer reports it.
        std::signal(SIGXFSZ, SIG_IGN);
    });
}

void checkOutputPath(const std::string& flag, const std::string& output, const std::vector<std::string>& inputs) {
    const fs::path target(output);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(folder)) throw InputError(flag + " " + output, "output folder does not exist");
    if (access(folder.c_str(), W_OK) != 0) throw InputError(flag + " " + output, "output folder is not writable");
    std::error_code error;
    const fs::file_status status = fs::symlink_status(target, error);
    if (fs::exists(status) && !fs::is_regular_file(status)) {
        throw InputError(flag + " " + output, "exists and is not a regular file; gvr replaces only files");
    }
    for (const std::string& input : inputs) {
        if (!input.empty() && sameFile(target, input)) {
            throw InputError(flag + " " + output, "is also an input; write the result to another file");
        }
    }
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    checkOutputPath("output", path, {});
    const fs::path target(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    // The temporary lives in the same folder so the final rename cannot cross devices,
    // and keeps the file's extension for writers that choose a format by it (nifticlib).
    const fs::path temporary = folder / (".tmp" + std::to_string(getpid()) + "-" + target.filename().string());
    if (temporary.native().size() >= sizeof(gTemporary)) throw InputError(path, "path is too long");
    std::lock_guard<std::mutex> lock(gWriting);
    std::strcpy(gTemporary, temporary.c_str());
    gHasTemporary = 1;
    try {
        write(temporary.string());
        fs::rename(temporary, target);
        gHasTemporary = 0;
    } catch (const fs::filesystem_error& failure) {
        gHasTemporary = 0;
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw InputError(path, std::string("cannot write: ") + failure.code().message());
    } catch (...) {
        gHasTemporary = 0;
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw;
    }
}

}  // namespace gvr
