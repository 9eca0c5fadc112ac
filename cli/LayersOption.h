/// @file LayersOption.h
/// @brief `--layers all|gaussians`: which of an asset's layers export, render, view
/// and probe read.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace gvr {

/// Adds --layers to @a command, into @a layers ("all" by default); @a where says
/// where the residual layer's bound holds, for the help.
CLI::Option* addLayersOption(CLI::App& command, std::string& layers, const std::string& where);

}  // namespace gvr
