/// @file VolumeOutputOptions.h
/// @brief The `-o` rule that ingest and export share: one output per extension,
/// and how what was written is reported.
#pragma once

#include "io/formats/VolumeOutputs.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace gvr {

/// Adds the repeatable `-o,--output` and `--float32` options.
void addVolumeOutputOptions(CLI::App& command, std::vector<std::string>& outputs, bool& float32);

/// Adds the removed `--format` option, hidden, so that old commands meet
/// rejectRemovedFormat()'s message instead of "unknown option".
void addRemovedFormatOption(CLI::App& command, std::string& format);

/// @throw InputError naming --format and the form that replaced it, when @a format was given.
void rejectRemovedFormat(const std::string& format);

/// Per written file: path, format, bytes, and for NIfTI its datatype and clamps.
nlohmann::json toJson(const std::vector<WrittenVolume>& written, const NiftiStorage& storage);

/// One "wrote PATH (SIZE)" line per file, saying what a NIfTI holds; the
/// float32 reason and clamped samples go to stderr as warnings.
void printWritten(const std::vector<WrittenVolume>& written, const NiftiStorage& storage);

}  // namespace gvr
