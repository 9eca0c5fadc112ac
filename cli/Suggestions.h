/// @file Suggestions.h
/// @brief "Did you mean ...?" for mistyped commands and flags.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace gvr {

/// The name in @a names nearest to @a typed (fewest single-character edits, or
/// the only name that @a typed begins), or "" when none is near enough to guess.
std::string closestName(const std::string& typed, const std::vector<std::string>& names);

/// The first argument that names no command of @a app ("gvr bogus"), with the
/// nearest command if there is one; "" when the command line names a command.
std::string unknownCommandMessage(const CLI::App& app, int argc, const char* const* argv);

/// For an argument list that @a app refused as unexpected: the first argument
/// that looks like a flag but names none of the parsed command's options, with
/// the nearest option; "" when there is no such argument.
std::string unknownFlagMessage(const CLI::App& app, int argc, const char* const* argv);

}  // namespace gvr
