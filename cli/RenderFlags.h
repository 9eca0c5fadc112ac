/// @file RenderFlags.h
/// @brief The flags that `gvr render` and `gvr view` share.
#pragma once

#include "render/ShearWarp.h"

#include <CLI/CLI.hpp>

#include <string>
#include <utility>

namespace gvr {

/// --stacks, --reuse-angle and --supersample. With @a automatic, --stacks also takes
/// auto, its default then, and *automatic says whether it was chosen (see automaticStacks).
void addStackFlags(CLI::App& command, ShearWarpSettings& settings, bool* automatic = nullptr);

/// "512x384" as --size gives it: width and height in pixels, each 1 to kMaxImageSide.
/// @throw InputError naming --size.
std::pair<int, int> parseImageSize(const std::string& text);

}  // namespace gvr
