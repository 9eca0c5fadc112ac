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

/// Calls @a write with a temporary path beside @a path, then renames it over @a path.
/// If @a write throws, the temporary file is removed and @a path is left untouched;
/// after removeTemporariesOnSignals(), a terminating signal does the same. SIGKILL
/// can leave a hidden ".tmpPID-name" file beside @a path, which the next write of
/// @a path removes once process PID is gone.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

/// Writes several files all or none: each @a writes[k] writes @a paths[k] (through
/// writeAtomically or not) under a hidden temporary name beside it; only when all
/// have succeeded are they renamed into place. A failure removes the temporaries
/// and leaves every earlier file as it was.
void writeAllOrNone(const std::vector<std::string>& paths,
                    const std::vector<std::function<void(const std::string&)>>& writes);

/// For programs such as the gvr command: from now on every signal that would end
/// the process (SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, ...) removes the
/// temporary of a write in progress, then ends the process by the same signal;
/// SIGXFSZ is ignored, so that a write past ulimit -f fails like a full disk
/// instead of killing the process. Opt-in, since a library must leave its host's
/// signals alone (Python's Ctrl-C, for one).
void removeTemporariesOnSignals();

}  // namespace gvr
