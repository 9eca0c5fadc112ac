/// @file MortonCode.h
/// @brief Morton (Z-order) codes of 3D cells: the storage order of assets and the
/// fit's order of Gaussians, so that neighbours in space lie near in memory.
#pragma once

#include <cstdint>

namespace gvr {

/// The low 21 bits of @a v, each moved to every third bit (bit i to bit 3i).
inline std::uint64_t spreadBits(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

/// The inverse of spreadBits: every third bit of @a v, gathered into the low 21.
inline std::uint64_t compactBits(std::uint64_t v) {
    v &= 0x1249249249249249ULL;
    v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ULL;
    v = (v ^ (v >> 4)) & 0x100f00f00f00f00fULL;
    v = (v ^ (v >> 8)) & 0x1f0000ff0000ffULL;
    v = (v ^ (v >> 16)) & 0x1f00000000ffffULL;
    v = (v ^ (v >> 32)) & 0x1fffff;
    return v;
}

/// The bits of x, y and z (21 each) interleaved, x lowest.
inline std::uint64_t mortonCode(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return spreadBits(x) | spreadBits(y) << 1 | spreadBits(z) << 2;
}

}  // namespace gvr
