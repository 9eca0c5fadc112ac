#include "render/ValueRange.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <vector>

namespace gvr {
namespace {

// Four lanes at a time and the remainder one by one: every length up to a few
// lanes past four must find its ends, wherever they lie.
TEST(ValueRange, FindsTheEndsAtEveryPlaceForEveryLength) {
    for (std::size_t size = 1; size <= 13; ++size) {
        for (std::size_t low = 0; low < size; ++low) {
            for (std::size_t high = 0; high < size; ++high) {
                if (high == low) continue;
                std::vector<float> values(size, 5.0f);
                values[low] = -3024.0f;
                values[high] = 3.0e38f;
                const auto [lo, hi] = valueRange(values.data(), size);
                EXPECT_EQ(lo, -3024.0f) << size << " " << low << " " << high;
                EXPECT_EQ(hi, 3.0e38f) << size << " " << low << " " << high;
            }
        }
    }
}

TEST(ValueRange, LeavesNaNOutAndGivesInfinitiesForNothing) {
    const float nan = std::nanf("");
    const std::vector<float> values = {nan, 2.0f, nan, -1.0f, nan, nan, 7.0f, nan, nan};
    const auto [lo, hi] = valueRange(values.data(), values.size());
    EXPECT_EQ(lo, -1.0f);
    EXPECT_EQ(hi, 7.0f);
    const std::vector<float> none = {nan, nan, nan, nan, nan};
    const auto [noLo, noHi] = valueRange(none.data(), none.size());
    EXPECT_EQ(noLo, INFINITY);
    EXPECT_EQ(noHi, -INFINITY);
    const auto [emptyLo, emptyHi] = valueRange(nullptr, 0);
    EXPECT_EQ(emptyLo, INFINITY);
    EXPECT_EQ(emptyHi, -INFINITY);
}

TEST(ValueRange, KeepsDenormalsAndTheFloatRangesEnds) {
    const std::vector<float> values = {1e-45f, 2e-45f, 1e-44f, 3e-45f, 5e-45f};
    const auto [lo, hi] = valueRange(values.data(), values.size());
    EXPECT_EQ(lo, 1e-45f);
    EXPECT_EQ(hi, 1e-44f);
    const std::vector<float> ends = {FLT_MAX, -FLT_MAX, 0.0f, 1.0f};
    const auto [least, greatest] = valueRange(ends.data(), ends.size());
    EXPECT_EQ(least, -FLT_MAX);
    EXPECT_EQ(greatest, FLT_MAX);
}

}  // namespace
}  // namespace gvr
