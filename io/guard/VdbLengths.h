/// @file VdbLengths.h
/// @brief Checks every length and size in a VDB file before OpenVDB trusts them.
///
/// OpenVDB sizes strings, metadata values and voxel buffers from lengths in the
/// file and fills them before its read can fail, and Debian's OpenVDB 10 reads an
/// uncompressed voxel block of whatever size the file states into a buffer of the
/// size it expects. One corrupt number costs gigabytes or corrupts the heap. The
/// numbers are cheap to walk: headers, metadata, the transform, and the tree's
/// masks and block sizes.
#pragma once

#include <string>

namespace gvr {

/// Walks the file as OpenVDB will read it: the header, the file metadata and,
/// grid by grid, the descriptor, the metadata (each fixed-size value's size
/// against its type, and the counts inside delayed-load metadata), the transform,
/// and the tree (node masks, and each compressed block against the size it must
/// decode to, Blosc's header included).
/// @return whether the file carries grid offsets (io::File may then seek to each grid).
/// @throw InputError naming @a path for a file without OpenVDB's magic number, for a
///        number that does not fit, for a format
///        version before 222 (OpenVDB 3.0), and for a grid type it cannot walk
///        (anything but the standard 5-4-3 trees of float, double, int32, int64,
///        vec3s, vec3d and vec3i).
bool checkVdbLengths(const std::string& path);

}  // namespace gvr
