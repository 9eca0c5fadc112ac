// Random streams from one seed: the same purpose and index give the same seed, and
// any other seed, purpose or index (high bits included) another one.

#include "pipeline/StreamSeed.h"

#include <gtest/gtest.h>

#include <set>

namespace gvr {
namespace {

TEST(StreamSeed, IsAFunctionOfSeedPurposeAndIndexAlone) {
    EXPECT_EQ(streamSeed(7, 1, 42), streamSeed(7, 1, 42));
    std::set<std::uint64_t> seen;
    for (std::uint64_t seed : {0ull, 1ull, 1ull << 32}) {
        for (std::uint64_t purpose : {1ull, 2ull, 3ull}) {
            for (std::uint64_t index : {0ull, 1ull, 2ull, 1ull << 32, (1ull << 32) + 1}) {
                EXPECT_TRUE(seen.insert(streamSeed(seed, purpose, index)).second)
                    << seed << " " << purpose << " " << index;
            }
        }
    }
}

}  // namespace
}  // namespace gvr
