/// @file AtomicFile.h
/// @brief Writes a file completely or not at all.
#pragma once

#include <functional>
#include <string>

namespace gvr {

/// Calls @a write with a temporary path beside @a path, then renames it over @a path.
/// If @a write throws, the temporary file is removed and @a path is left untouched.
void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

}  // namespace gvr
