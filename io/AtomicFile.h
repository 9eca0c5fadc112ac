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
/// If @a write throws, or the process gets SIGINT or SIGTERM meanwhile, the
/// temporary file is removed and @a path is left untouched. (SIGKILL can leave a
/// hidden ".tmpPID-name" file beside @a path.) SIGXFSZ is ignored from then on, so
/// that a write past ulimit -f fails like a full disk instead of killing gvr.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

}  // namespace gvr
