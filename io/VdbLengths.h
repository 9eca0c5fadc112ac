/// @file VdbLengths.h
/// @brief Checks the lengths in a VDB file's headers before OpenVDB trusts them.
///
/// OpenVDB sizes every string and metadata value from a 32-bit length in the file
/// and fills the buffer before its read can fail, so one corrupt length costs up to
/// 4 GiB. The lengths sit in a few places that are cheap to walk: the file's
/// metadata, each grid's descriptor, and each grid's metadata.
#pragma once

#include <string>

namespace gvr {

/// Walks the header, the file metadata and, grid by grid, each descriptor, its
/// metadata and its transform's type name, checking every length against the bytes left in the file, each
/// fixed-size metadata value's size against its type, and the counts inside
/// delayed-load metadata, from which OpenVDB would otherwise allocate. Grids after
/// the first are reached through the descriptors' offsets, which files written by
/// io::File carry; in a file without them only the first grid is checked.
/// @return whether the file carries grid offsets (io::File may then seek to each grid).
/// @throw InputError naming @a path for a length that runs past the end.
bool checkVdbLengths(const std::string& path);

}  // namespace gvr
