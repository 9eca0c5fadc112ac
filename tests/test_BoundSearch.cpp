// The bound search against an exhaustive scan of the same ladder: it must find the
// smallest bound that fits, in far fewer tries than there are bounds.

#include "workflow/BoundSearch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>

namespace gvr {
namespace {

/// The first index whose bytes fit, by trying every one.
std::size_t firstFitting(const BoundLadder& ladder, std::uint64_t maxBytes,
                         const std::function<std::uint64_t(double)>& bytesAt) {
    for (std::size_t i = 0; i < ladder.size(); ++i) {
        if (bytesAt(ladder.bound(i)) <= maxBytes) return i;
    }
    return ladder.size();
}

/// A layer's bytes as a coder's fall: a bit a voxel per halving of the bound, then a
/// floor of the Gaussians and the predictors.
std::uint64_t modelBytes(double bound, double spread) {
    const double bitsPerVoxel = std::max(0.0, std::log2(spread / std::max(bound, 1e-30)) + 1.0);
    return std::uint64_t(1e6 * bitsPerVoxel / 8.0) + 20000;
}

void expectSmallestFitting(const BoundLadder& ladder, std::uint64_t budget,
                           const std::function<std::uint64_t(double)>& bytes, int maxEncodes) {
    const std::optional<SearchedBound> found = smallestBoundWithin(ladder, budget, bytes);
    ASSERT_TRUE(found) << budget;
    EXPECT_DOUBLE_EQ(found->bound, ladder.bound(firstFitting(ladder, budget, bytes))) << budget;
    EXPECT_LE(found->bytes, budget);
    EXPECT_LE(found->encodes, maxEncodes) << budget << " bytes, found " << found->bound;
}

TEST(BoundSearch, FindsTheSmallestWholeSampleBoundThatFitsInAFewEncodes) {
    const BoundLadder ladder = BoundLadder::wholeSamples(7.11, 3000.0);  // a uint8 CT's HU a sample
    const auto bytes = [](double bound) { return modelBytes(bound + 3.0, 4000.0); };
    for (const std::uint64_t budget : {200000ull, 400000ull, 800000ull})
        expectSmallestFitting(ladder, budget, bytes, 7);
}

TEST(BoundSearch, WhereTheBytesLevelOffItTakesAtMostTwiceABisection) {
    const BoundLadder ladder = BoundLadder::wholeSamples(7.11, 3000.0);
    const auto bytes = [](double bound) { return modelBytes(bound + 3.0, 400.0); };  // flat from 400 HU up
    const int bisection = int(std::ceil(std::log2(double(ladder.size())))) + 2;      // and the two ends
    for (const std::uint64_t budget : {30000ull, 100000ull})
        expectSmallestFitting(ladder, budget, bytes, 2 * bisection);
}

TEST(BoundSearch, FindsAFloatBoundWithinTwoPercent) {
    const BoundLadder ladder = BoundLadder::values(2.5);
    const auto bytes = [](double bound) { return modelBytes(bound, 0.3); };
    expectSmallestFitting(ladder, 250000, bytes, 7);
    const double found = smallestBoundWithin(ladder, 250000, bytes)->bound;
    EXPECT_GT(bytes(found / 1.021), 250000u);  // a bound 2 % smaller is over
}

TEST(BoundSearch, LosslessWhenItFitsAndNothingWhenNoBoundDoes) {
    const BoundLadder ladder = BoundLadder::wholeSamples(1.0, 255.0);
    const auto bytes = [](double bound) { return modelBytes(bound + 1.0, 40.0); };
    EXPECT_DOUBLE_EQ(smallestBoundWithin(ladder, 10000000, bytes)->bound, 0.0);
    EXPECT_FALSE(smallestBoundWithin(ladder, 1000, bytes));
}

TEST(BoundSearch, AWholeSampleBoundIsNeverAHairUnderItsSamples) {
    const BoundLadder ladder = BoundLadder::wholeSamples(0.1, 100.0);
    for (std::size_t k = 0; k < ladder.size(); ++k) {
        EXPECT_EQ(std::floor(ladder.bound(k) / 0.1), double(k)) << k;
        EXPECT_NEAR(ladder.bound(k), 0.1 * double(k), 1e-12);
    }
    EXPECT_GE(ladder.bound(ladder.size() - 1), 100.0);
    const BoundLadder rounded = BoundLadder::wholeSamples(7.1098, 3000.0, 4.9e-4);
    EXPECT_EQ(rounded.bound(0), 0.0);  // lossless needs no room for rounding
    EXPECT_DOUBLE_EQ(rounded.bound(2), 2 * 7.1098 + 4.9e-4);
}

}  // namespace
}  // namespace gvr
