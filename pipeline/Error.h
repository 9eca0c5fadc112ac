/// @file Error.h
/// @brief The exception type for problems with what the user gave us.
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
        : std::runtime_error(culprit + ": " + problem) {}
};

}  // namespace gvr
