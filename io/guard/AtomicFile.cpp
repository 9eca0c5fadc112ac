#include "io/guard/AtomicFile.h"

#include "io/formats/Readers.h"
#include "io/guard/InputFile.h"
#include "pipeline/Error.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <system_error>

namespace gvr {

namespace {

namespace fs = std::filesystem;

/// What a terminating signal removes: the temporaries of the writes in progress
/// and the files written in place. Plain bytes in fixed slots, since a handler may
/// only call async-signal-safe functions such as unlink and rmdir.
struct SignalSlot {
    char path[4096];
    bool folder;
    unsigned long order;  // folders nest in the order they were made
    volatile std::sig_atomic_t used;
};
constexpr int kSignalSlots = 64;
SignalSlot gSlots[kSignalSlots];
unsigned long gNextOrder = 0;
std::mutex gSlotsLock;

/// A free slot holding @a path; -1 when all are taken (then only the stale cleaner
/// removes what a signal leaves).
void requireSlotLength(const fs::path& path) {
    if (path.native().size() >= sizeof(SignalSlot::path)) throw InputError(path.string(), "path is too long");
}

int takeSlot(const fs::path& path, bool folder) {
    requireSlotLength(path);
    std::lock_guard<std::mutex> lock(gSlotsLock);
    for (int k = 0; k < kSignalSlots; ++k) {
        if (gSlots[k].used) continue;
        std::strcpy(gSlots[k].path, path.c_str());
        gSlots[k].folder = folder;
        gSlots[k].order = gNextOrder++;
        gSlots[k].used = 1;
        return k;
    }
    return -1;
}

void releaseSlot(int slot) {
    if (slot < 0) return;
    std::lock_guard<std::mutex> lock(gSlotsLock);
    gSlots[slot].used = 0;
}

/// SaidOnSignal's line, in plain bytes for the handler's write().
char gFarewell[4096];
volatile std::sig_atomic_t gFarewellBytes = 0;
volatile std::sig_atomic_t gFarewellFd = STDERR_FILENO;

extern "C" void removeTemporariesAndExit(int signal) {
    if (gFarewellBytes > 0) {
        const ssize_t ignored = write(gFarewellFd, gFarewell, std::size_t(gFarewellBytes));
        (void)ignored;  // nothing else to do on a failed write in a handler
    }
    for (const SignalSlot& slot : gSlots) {
        if (slot.used && !slot.folder) unlink(slot.path);
    }
    // Deepest folder first: a nested write's folder lies inside its caller's.
    for (unsigned long below = ~0ul;;) {
        int deepest = -1;
        for (int k = 0; k < kSignalSlots; ++k) {
            if (gSlots[k].used && gSlots[k].folder && gSlots[k].order < below &&
                (deepest < 0 || gSlots[k].order > gSlots[deepest].order)) {
                deepest = k;
            }
        }
        if (deepest < 0) break;
        rmdir(gSlots[deepest].path);
        below = gSlots[deepest].order;
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

bool sameFile(const fs::path& a, const fs::path& b) {
    std::error_code error;
    if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
    return fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
}

const std::string kStagingPrefix = ".gvr-";

/// The pid in a staging folder's name ".gvr-<pid>-XXXXXX", or 0 for any other name.
pid_t stagingPid(const std::string& name) {
    constexpr std::size_t kRandomChars = 6;  // mkdtemp's XXXXXX
    if (name.rfind(kStagingPrefix, 0) != 0) return 0;
    const std::size_t dash = name.find('-', kStagingPrefix.size());
    if (dash == std::string::npos || name.size() != dash + 1 + kRandomChars) return 0;
    const std::string digits = name.substr(kStagingPrefix.size(), dash - kStagingPrefix.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
    return pid_t(std::stol(digits));
}

/// True when process @a pid no longer runs, or is a zombie that its parent has not
/// yet reaped (as after a SIGKILL whose sender runs gvr again before waiting).
bool processIsGone(pid_t pid) {
    if (kill(pid, 0) != 0) return errno == ESRCH;
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    std::getline(stat, line);
    const std::size_t paren = line.rfind(')');
    return paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] == 'Z';
}

/// Removes what the writes of processes that are gone (killed with SIGKILL, or by
/// a power cut) left in @a folder: staging folders of this user, of mode 0700 as
/// mkdtemp makes them, whose pid no longer runs. Nothing else, so that an input
/// whose name only looks like a temporary stays.
void removeStaleTemporaries(const fs::path& folder) {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(folder, error)) {
        const pid_t pid = stagingPid(entry.path().filename().string());
        struct stat info {};
        if (pid == 0 || pid == getpid() || lstat(entry.path().c_str(), &info) != 0) continue;
        if (!S_ISDIR(info.st_mode) || info.st_uid != geteuid() || (info.st_mode & 07777) != 0700) continue;
        if (!processIsGone(pid)) continue;
        std::error_code ignored;
        fs::remove_all(entry.path(), ignored);
    }
}

fs::path folderOf(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

/// A folder that only this process can write, made beside an output so that the
/// final rename cannot cross devices, and removed with all it holds when it goes.
/// Its name cannot be foreseen, so nothing can be planted in it beforehand.
class StagingFolder {
public:
    explicit StagingFolder(const fs::path& beside) {
        removeStaleTemporaries(beside);
        std::string name = (beside / (kStagingPrefix + std::to_string(getpid()) + "-XXXXXX")).string();
        requireSlotLength(name);  // before the folder exists, which a throw would leave behind
        if (!mkdtemp(name.data())) {
            throw InputError(name, std::string("cannot make a temporary folder: ") + std::strerror(errno));
        }
        mPath = name;
        mSlot = takeSlot(mPath, true);
    }
    StagingFolder(const StagingFolder&) = delete;
    StagingFolder& operator=(const StagingFolder&) = delete;
    ~StagingFolder() {
        std::error_code ignored;
        fs::remove_all(mPath, ignored);
        for (const int slot : mFileSlots) releaseSlot(slot);
        releaseSlot(mSlot);
    }

    /// The path of a file @a name in it, which a signal removes from now on.
    fs::path file(const fs::path& name) {
        const fs::path path = mPath / name;
        mFileSlots.push_back(takeSlot(path, false));
        return path;
    }

private:
    fs::path mPath;
    int mSlot = -1;
    std::vector<int> mFileSlots;
};

/// Renames each of @a staged over @a targets, in order. When one rename fails, the
/// targets already replaced get their earlier files back, from hard links kept in
/// @a folders (or are removed when they had none), and the failure is thrown.
void renameAllIntoPlace(const std::vector<fs::path>& staged, const std::vector<std::string>& targets,
                        std::vector<std::unique_ptr<StagingFolder>>& folders) {
    std::vector<fs::path> previous(targets.size());
    for (std::size_t k = 0; k < targets.size(); ++k) {
        std::error_code error;
        if (!fs::exists(fs::symlink_status(targets[k], error))) continue;
        previous[k] = folders[k]->file(fs::path(targets[k]).filename().string() + ".previous");
        fs::create_hard_link(targets[k], previous[k], error);
        if (error) previous[k].clear();
    }
    for (std::size_t k = 0; k < targets.size(); ++k) {
        std::error_code error;
        fs::rename(staged[k], targets[k], error);
        if (!error) continue;
        for (std::size_t j = 0; j < k; ++j) {
            std::error_code ignored;
            if (previous[j].empty()) {
                fs::remove(targets[j], ignored);
            } else {
                fs::rename(previous[j], targets[j], ignored);
            }
        }
        throw InputError(targets[k], "cannot rename the finished file into place: " + error.message() +
                                         "; every output is as it was");
    }
}

}  // namespace

RemovedOnSignal::RemovedOnSignal(const std::string& path) : mSlot(takeSlot(path, false)) {}

RemovedOnSignal::~RemovedOnSignal() { releaseSlot(mSlot); }

void writeAllOrNone(const std::vector<std::string>& paths,
                    const std::vector<std::function<void(const std::string&)>>& writes) {
    std::vector<std::unique_ptr<StagingFolder>> folders;
    std::vector<fs::path> staged;
    for (std::size_t k = 0; k < paths.size(); ++k) {
        const fs::path target(paths[k]);
        folders.push_back(std::make_unique<StagingFolder>(folderOf(target)));
        staged.push_back(folders.back()->file(target.filename()));
        writes[k](staged.back().string());
    }
    renameAllIntoPlace(staged, paths, folders);
}

SaidOnSignal::SaidOnSignal(const std::string& line, int fd) {
    const std::string text = line.substr(0, sizeof gFarewell - 1) + "\n";
    gFarewellBytes = 0;
    gFarewellFd = fd;
    std::memcpy(gFarewell, text.data(), text.size());
    gFarewellBytes = std::sig_atomic_t(text.size());
}

SaidOnSignal::~SaidOnSignal() { gFarewellBytes = 0; }

void removeTemporariesOnSignals() {
    static std::once_flag installed;
    std::call_once(installed, [] {
        // Every signal whose default ends the process; SIGKILL cannot be caught, so
        // its temporaries are removed by the next write of the same output.
        for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGPIPE, SIGVTALRM, SIGPROF}) {
            struct sigaction action {};
            action.sa_handler = removeTemporariesAndExit;
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
    try {
        StagingFolder staging(folderOf(target));
        const fs::path temporary = staging.file(target.filename());
        write(temporary.string());
        fs::rename(temporary, target);
    } catch (const fs::filesystem_error& failure) {
        throw InputError(path, std::string("cannot write: ") + failure.code().message());
    }
}

}  // namespace gvr
