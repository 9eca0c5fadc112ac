// Morton codes: the fit's order of Gaussians and an asset's storage order share one
// interleave, and compactBits undoes spreadBits.

#include "pipeline/MortonCode.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace gvr {
namespace {

/// The interleave bit by bit, as the definition states it.
std::uint64_t interleavedBitByBit(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    std::uint64_t code = 0;
    for (int bit = 0; bit < 21; ++bit) {
        code |= (std::uint64_t(x >> bit & 1u) << (3 * bit)) | (std::uint64_t(y >> bit & 1u) << (3 * bit + 1)) |
                (std::uint64_t(z >> bit & 1u) << (3 * bit + 2));
    }
    return code;
}

TEST(MortonCode, InterleavesTwentyOneBitsOfEachAxisXLowest) {
    const std::uint32_t top = (1u << 21) - 1;
    for (const std::uint32_t v : {0u, 1u, 2u, 5u, 1000u, 123457u, top}) {
        EXPECT_EQ(mortonCode(v, 0, 0), interleavedBitByBit(v, 0, 0)) << v;
        EXPECT_EQ(mortonCode(v, top - v, v / 3), interleavedBitByBit(v, top - v, v / 3)) << v;
        EXPECT_EQ(compactBits(spreadBits(v)), v) << v;
    }
    EXPECT_EQ(mortonCode(1, 0, 0), 1u);
    EXPECT_EQ(mortonCode(0, 1, 0), 2u);
    EXPECT_EQ(mortonCode(0, 0, 1), 4u);
    EXPECT_EQ(mortonCode(top, top, top), (std::uint64_t(1) << 63) - 1);
    EXPECT_EQ(spreadBits(std::uint64_t(1) << 21), 0u);  // only the low 21 bits count
}

}  // namespace
}  // namespace gvr
