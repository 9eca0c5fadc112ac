/// @file ChildProcess.h
/// @brief Runs another program to completion and measures it: what the batch
/// benchmark uses so that every run is isolated, timed and sized on its own.
#pragma once

#include <string>
#include <vector>

namespace gvr {

struct ChildResult {
    int exitCode = -1;      ///< the program's exit code, or 128 + signal when killed
    double seconds = 0.0;   ///< wall-clock time
    double peakRssMiB = 0;  ///< the child's peak resident memory
    std::string output;     ///< what it wrote to stdout, up to 16 MiB
    std::string lastError;  ///< the last non-empty line it wrote to stderr
    bool timedOut = false;  ///< killed for running past its time limit

    bool ok() const { return exitCode == 0; }
};

/// Runs @a argv (argv[0] is the executable's path), with stdin from /dev/null, the
/// first 16 MiB of stdout kept in memory, stderr appended to @a logPath, and no
/// other descriptor of this process. The child is killed if this process dies, so
/// a killed benchmark leaves no orphan writing into its folders. With a positive
/// @a timeoutSeconds the child runs in its own process group, and the whole group
/// is killed once that time has passed, or once the child ends (what it left
/// running). The run ends when the child does, whoever holds its output open.
ChildResult runChild(const std::vector<std::string>& argv, const std::string& logPath, double timeoutSeconds = 0);

/// The path of the running executable, for running gvr's own subcommands.
std::string currentExecutable();

}  // namespace gvr
