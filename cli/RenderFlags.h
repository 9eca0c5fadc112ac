/// @file RenderFlags.h
/// @brief The flags that `gvr render` and `gvr view` share.
#pragma once

#include "render/ShearWarp.h"

#include <CLI/CLI.hpp>

#include <string>
#include <utility>

namespace gvr {

/// --stacks, --reuse-angle and --supersample.
void addStackFlags(CLI::App& command, ShearWarpSettings& settings);

/// "512x384" as --size gives it: width and height in pixels, each 1 to kMaxImageSide.
/// @throw InputError naming --size.
std::pair<int, int> parseImageSize(const std::string& text);

}  // namespace gvr
