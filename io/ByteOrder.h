/// @file ByteOrder.h
/// @brief Byte swapping for formats that store big-endian samples.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace gvr {

inline bool hostIsBigEndian() {
    const std::uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 0;
}

/// Reverses the bytes of each @a width-byte word in place.
inline void swapBytes(unsigned char* data, std::size_t wordCount, std::size_t width) {
    if (width < 2) return;
    for (std::size_t w = 0; w < wordCount; ++w) std::reverse(data + w * width, data + (w + 1) * width);
}

/// Converts words stored with the given byte order to the host's order.
inline void toHostOrder(unsigned char* data, std::size_t wordCount, std::size_t width,
                        bool storedBigEndian) {
    if (storedBigEndian != hostIsBigEndian()) swapBytes(data, wordCount, width);
}

}  // namespace gvr
