// Words in a stated byte order: loaded the same on any host, and written
// little-endian whatever the host.

#include "io/guard/ByteOrder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace gvr {
namespace {

TEST(ByteOrder, WordsLoadAndStoreInTheStatedOrderOnAnyHost) {
    const unsigned char bytes[4] = {0x12, 0x34, 0x56, 0x78};
    EXPECT_EQ(loadWord<std::uint32_t>(bytes, /*storedBigEndian=*/true), 0x12345678u);
    EXPECT_EQ(loadWord<std::uint32_t>(bytes, false), 0x78563412u);
    EXPECT_EQ(loadLittleEndian<std::uint16_t>(bytes + 2), 0x7856u);
    EXPECT_EQ(loadWord<std::int16_t>(bytes, true), std::int16_t(0x1234));

    std::string stored;
    appendLittleEndian(stored, std::uint32_t(0x01020304));
    appendLittleEndian(stored, -1.5f);
    appendLittleEndian(stored, 2.25);
    ASSERT_EQ(stored.size(), 16u);
    EXPECT_EQ(stored.substr(0, 4), std::string("\x04\x03\x02\x01", 4));
    EXPECT_EQ(stored.substr(4, 4), std::string("\x00\x00\xc0\xbf", 4)) << "-1.5f is 0xbfc00000";
    EXPECT_EQ(loadLittleEndian<float>(stored.data() + 4), -1.5f);
    EXPECT_EQ(loadLittleEndian<double>(stored.data() + 8), 2.25);
}

TEST(ByteOrder, SwapsEachWordInPlace) {
    unsigned char words[6] = {1, 2, 3, 4, 5, 6};
    swapBytes(words, 2, 3);
    const unsigned char expected[6] = {3, 2, 1, 6, 5, 4};
    EXPECT_TRUE(std::equal(words, words + 6, expected));
    swapBytes(words, 6, 1);  // one-byte words stay
    EXPECT_TRUE(std::equal(words, words + 6, expected));
}

}  // namespace
}  // namespace gvr
