/// @file Commands.h
/// @brief The gvr subcommands; each adds itself to the application, from its own file.
#pragma once

#include <CLI/CLI.hpp>

namespace gvr {

void addIngestCommand(CLI::App& app);
void addInfoCommand(CLI::App& app);
void addFitCommand(CLI::App& app);
void addMergeCommand(CLI::App& app);
void addExportCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addProbeCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addBaselineCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);

/// Every subcommand above, in the order `gvr --help` lists them.
void addCommands(CLI::App& app);

}  // namespace gvr
