/// @file ByteOrder.h
/// @brief Words as files store them: byte swapping for samples, and the one way
/// every reader and writer of gvr loads or stores a header field in a stated order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

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
inline void toHostOrder(unsigned char* data, std::size_t wordCount, std::size_t width, bool storedBigEndian) {
    if (storedBigEndian != hostIsBigEndian()) swapBytes(data, wordCount, width);
}

/// The @a T (an integer or float) whose bytes start at @a bytes, stored in the given order.
template <typename T>
T loadWord(const void* bytes, bool storedBigEndian) {
    unsigned char word[sizeof(T)];
    std::memcpy(word, bytes, sizeof(T));
    toHostOrder(word, 1, sizeof(T), storedBigEndian);
    T value;
    std::memcpy(&value, word, sizeof(T));
    return value;
}

template <typename T>
T loadLittleEndian(const void* bytes) {
    return loadWord<T>(bytes, false);
}

/// Reads a little-endian T at @a cursor and moves the cursor past it.
template <typename T, typename Byte>
T takeLittleEndian(const Byte*& cursor) {
    static_assert(sizeof(Byte) == 1, "a cursor over bytes");
    const T value = loadLittleEndian<T>(cursor);
    cursor += sizeof(T);
    return value;
}

/// Appends @a value to @a bytes little-endian, whatever the host's order.
template <typename T>
void appendLittleEndian(std::string& bytes, T value) {
    unsigned char word[sizeof(T)];
    std::memcpy(word, &value, sizeof(T));
    toHostOrder(word, 1, sizeof(T), /*storedBigEndian=*/false);  // a swap is its own inverse
    bytes.append(reinterpret_cast<const char*>(word), sizeof(T));
}

}  // namespace gvr
