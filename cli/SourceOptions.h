/// @file SourceOptions.h
/// @brief The flags that say how to read a source volume, shared by ingest and info.
#pragma once

#include "io/Ingest.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace gvr {

struct SourceFlags {
    int volume = 0;
    std::vector<double> spacing;
    std::vector<std::int64_t> rawDims;
    std::string rawType;
    std::string endian = "little";
    std::uint64_t headerBytes = 0;
    int rawChannels = 1;
    std::optional<double> threshold, thresholdAbove;
    std::string flip;
    std::optional<float> nanTo;
    std::string modality;
    bool dataFilesAnywhere = false;
};

/// Adds --volume, --spacing, --raw-*, --threshold, --nan-to and --modality to @a command;
/// without @a withThreshold, leaves --threshold to the command (eval gives it another meaning).
void addSourceFlags(CLI::App& command, SourceFlags& flags, bool withThreshold = true);

/// Checks the flags together and turns them into ingest options.
/// @throw InputError naming the offending flag.
IngestOptions toIngestOptions(const SourceFlags& flags);

}  // namespace gvr
