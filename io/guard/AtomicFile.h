/// @file AtomicFile.h
/// @brief Writes a file completely or not at all, and never over what it must not touch.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace gvr {

/// Checks, before any work, that @a output (named by @a flag in errors) can be
/// written: its folder exists and is writable, it is no input of the command, and
/// it is not a FIFO, device or folder that a rename would replace.
/// @throw InputError naming the flag and the path otherwise
void checkOutputPath(const std::string& flag, const std::string& output, const std::vector<std::string>& inputs);

/// Calls @a write with a temporary path, then renames it over @a path. The
/// temporary lies in a folder that mkdtemp made beside @a path (".gvr-PID-XXXXXX",
/// mode 0700), so that no one can plant a link or a FIFO where it is written. If
/// @a write throws, the folder is removed and @a path is left untouched; after
/// removeTemporariesOnSignals(), a terminating signal does the same. SIGKILL can
/// leave the folder behind, which the next write into the same folder removes once
/// process PID is gone.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes several files all or none: each @a writes[k] writes @a paths[k] (through
/// writeAtomically or not) at a temporary path as above; only when all have
/// succeeded are they renamed into place. A failure, a rename's included, removes
/// the temporaries and leaves every earlier file as it was.
void writeAllOrNone(const std::vector<std::string>& paths,
                    const std::vector<std::function<void(const std::string&)>>& writes);

/// While it lives, a terminating signal (after removeTemporariesOnSignals()) removes
/// the file at @a path: for a file written in place, such as a log that can be
/// watched as it grows, which a killed command must not leave half written.
class RemovedOnSignal {
public:
    explicit RemovedOnSignal(const std::string& path);
    RemovedOnSignal(const RemovedOnSignal&) = delete;
    RemovedOnSignal& operator=(const RemovedOnSignal&) = delete;
    ~RemovedOnSignal();

private:
    int mSlot;
};

/// While it lives, a terminating signal (after removeTemporariesOnSignals()) writes
/// @a line to descriptor @a fd (stderr, or wherever the program's messages go)
/// before the process ends: what a user stopping a long command needs to know, such
/// as how to carry on. The latest one alive is said.
class SaidOnSignal {
public:
    SaidOnSignal(const std::string& line, int fd);
    SaidOnSignal(const SaidOnSignal&) = delete;
    SaidOnSignal& operator=(const SaidOnSignal&) = delete;
    ~SaidOnSignal();
};

/// For programs such as the gvr command: from now on every signal that would end
/// the process (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, ...) removes the
/// temporaries of the writes in progress and the files RemovedOnSignal names, then ends the process by the same signal;
/// SIGXFSZ is ignored, so that a write past ulimit -f fails like a full disk
/// instead of killing the process. Opt-in, since a library must leave its host's
/// signals alone (Python's Ctrl-C, for one).
void removeTemporariesOnSignals();

}  // namespace gvr
