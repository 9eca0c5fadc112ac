/// @file FramePath.h
/// @brief How `gvr render --orbit` names its frames, so that the benchmark finds them.
#pragma once

#include <string>

namespace gvr {

/// frame.png -> frame_0007.png for frame 7 of @a count; unchanged for a single frame.
std::string framePath(const std::string& output, int index, int count);

}  // namespace gvr
