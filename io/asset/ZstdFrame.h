/// @file ZstdFrame.h
/// @brief Length-prefixed zstd frames, as the asset's streams are stored: a uint32
/// (little-endian) byte count, then one frame holding a known number of bytes.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace gvr {

/// Appends @a plain to @a out as a length and one zstd frame at @a level.
void appendZstdFrame(std::string& out, std::string_view plain, int level);

/// The bytes of the frame at @a cursor in @a body, which must hold exactly
/// @a expectedBytes (checked before anything is allocated); moves @a cursor past it.
/// @throw std::runtime_error naming @a what when the frame is cut short or holds another size.
std::string takeZstdFrame(std::string_view body, std::size_t& cursor, std::size_t expectedBytes, const char* what);

}  // namespace gvr
