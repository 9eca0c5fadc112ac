/// @file Error.h
/// @brief The exception types: problems with what the user gave us, and work the
/// caller cancelled.
#pragma once

#include <stdexcept>
#include <string>

namespace gvr {

/// A problem with the user's input: a file, a flag or the data itself.
/// The message names the culprit first ("scan.nii.gz: truncated ..."), so the
/// command line can print it as one line and exit with code 2.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& culprit, const std::string& problem)
        : std::runtime_error(culprit + ": " + oneLine(problem)) {}

private:
    /// Libraries' error texts may span lines ("PNG read error: ...\nPNG library
    /// error"); the message stays one line.
    static std::string oneLine(std::string text) {
        while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
        for (std::size_t at = text.find_first_of("\r\n"); at != std::string::npos;
             at = text.find_first_of("\r\n", at)) {
            const bool windowsBreak = text.compare(at, 2, "\r\n") == 0;
            text.replace(at, windowsBreak ? 2 : 1, "; ");
        }
        return text;
    }
};

/// A long call stopped because its caller asked it to (a cancel flag), not
/// because anything failed.
class Cancelled : public std::runtime_error {
public:
    explicit Cancelled(const std::string& what) : std::runtime_error(what + ": cancelled") {}
};

}  // namespace gvr
