#include "io/AtomicFile.h"

#include "io/InputFile.h"
#include "io/Readers.h"
#include "pipeline/Error.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <functional>
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

const std::string kTemporaryPrefix = ".tmp";

/// What follows ".tmp<pid>-" in a temporary's name: the target's own name when the
/// whole fits in a file name (255 bytes), else a hash of it. Either way the name
/// keeps the extension, since some writers choose a format by it (nifticlib:
/// .nii.gz included).
std::string temporarySuffix(const std::string& name) {
    constexpr std::size_t kNameMax = 255, kPrefixMax = 4 + 10 + 1;  // ".tmp", a pid, "-"
    if (name.size() + kPrefixMax <= kNameMax) return name;
    const std::size_t dot = name.find('.', name.size() - std::min<std::size_t>(name.size(), 16));
    return std::to_string(std::hash<std::string>{}(name)) + (dot == std::string::npos ? "" : name.substr(dot));
}

/// Removes the temporaries of the same output left by processes that are gone
/// (killed with SIGKILL, or by a power cut): ".tmp<pid>-<suffix>" whose pid no
/// longer runs.
void removeStaleTemporaries(const fs::path& folder, const std::string& suffix) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(folder, error)) {
        const std::string name = entry.path().filename().string();
        const std::size_t dash = name.find('-');
        if (name.rfind(kTemporaryPrefix, 0) != 0 || dash == std::string::npos || name.substr(dash + 1) != suffix) continue;
        const std::string digits = name.substr(kTemporaryPrefix.size(), dash - kTemporaryPrefix.size());
        if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid == getpid() || kill(pid, 0) == 0 || errno != ESRCH) continue;
        std::error_code ignored;
        fs::remove(entry.path(), ignored);
    }
}

fs::path folderOf(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

/// Where a write goes first: in the target's @a folder, so that the final rename
/// cannot cross devices, hidden, and named for this process and the target (@a suffix).
fs::path temporaryPathFor(const fs::path& folder, const std::string& suffix) {
    return folder / (kTemporaryPrefix + std::to_string(getpid()) + "-" + suffix);
}

}  // namespace

void writeAllOrNone(const std::vector<std::string>& paths,
                    const std::vector<std::function<void(const std::string&)>>& writes) {
    std::vector<fs::path> staged;
    try {
        for (std::size_t k = 0; k < paths.size(); ++k) {
            // "all-" keeps the staged file apart from the temporary that a writer's
            // own writeAtomically makes beside it.
            const fs::path target(paths[k]);
            const fs::path folder = folderOf(target);
            const std::string suffix = temporarySuffix("all-" + target.filename().string());
            removeStaleTemporaries(folder, suffix);
            const fs::path staging = temporaryPathFor(folder, suffix);
            writes[k](staging.string());
            staged.push_back(staging);
        }
        for (std::size_t k = 0; k < paths.size(); ++k) fs::rename(staged[k], paths[k]);
    } catch (...) {
        std::error_code ignored;
        for (const fs::path& file : staged) fs::remove(file, ignored);
        throw;
    }
}

void removeTemporariesOnSignals() {
    static std::once_flag installed;
    std::call_once(installed, [] {
        // Every signal whose default ends the process; SIGKILL cannot be caught, so
        // its temporaries are removed by the next write of the same output.
        for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGPIPE, SIGVTALRM, SIGPROF}) {
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
    requireNoNulByte(output);
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
        if (input.empty()) continue;
        for (const std::string& file : filesReadFrom(input)) {
            if (!sameFile(target, file)) continue;
            const std::string which = file == input ? "is also an input" : "is one of the files read from " + input;
            throw InputError(flag + " " + output, which + "; write the result to another file");
        }
    }
}

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    checkOutputPath("output", path, {});
    const fs::path target(path);
    const fs::path folder = folderOf(target);
    const std::string suffix = temporarySuffix(target.filename().string());
    const fs::path temporary = temporaryPathFor(folder, suffix);
    if (temporary.native().size() >= sizeof(gTemporary)) throw InputError(path, "path is too long");
    std::lock_guard<std::mutex> lock(gWriting);
    removeStaleTemporaries(folder, suffix);
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
