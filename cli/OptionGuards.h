/// @file OptionGuards.h
/// @brief Checks every command's options get, whoever declared them.
#pragma once

#include <CLI/CLI.hpp>

namespace gvr {

/// Refuses a negative value for every unsigned option of @a app and its
/// subcommands. CLI11 reads them with strtoull, which wraps "-1" to 2^64 - 1, so
/// that "--iterations -1" would run forever and "--gaussians -5" would fit some
/// other count.
void refuseNegativeUnsignedValues(CLI::App& app);

/// Usage errors as one line, "gvr: error: ...", like every other error.
void useOneLineUsageErrors(CLI::App& app);

}  // namespace gvr
