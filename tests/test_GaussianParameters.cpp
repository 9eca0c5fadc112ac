// The parameter arrays' layout and bookkeeping: every group must move together,
// or a Gaussian's mean would end up with another one's colour.

#include "pipeline/GaussianParameters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gvr {
namespace {

/// Gaussian i holds 100 * i + 10 * g + k in element k of group g: any mix-up shows.
GaussianParameters tagged(std::size_t count, int channels) {
    GaussianParameters params(count, channels);
    for (std::size_t i = 0; i < count; ++i) {
        for (int g = 0; g < kGroupCount; ++g) {
            for (int k = 0; k < params.width(ParameterGroup(g)); ++k) {
                params.at(ParameterGroup(g), i)[k] = float(100 * i + 10 * g + k);
            }
        }
    }
    return params;
}

/// Whether @a params' Gaussian @a at carries the tag of Gaussian @a original.
void expectTag(const GaussianParameters& params, std::size_t at, std::size_t original) {
    for (int g = 0; g < kGroupCount; ++g) {
        for (int k = 0; k < params.width(ParameterGroup(g)); ++k) {
            EXPECT_EQ(params.at(ParameterGroup(g), at)[k], float(100 * original + 10 * g + k))
                << groupName(ParameterGroup(g)) << "[" << k << "] of Gaussian " << at;
        }
    }
}

TEST(GaussianParameters, GroupWidthsAndNames) {
    EXPECT_EQ(groupWidth(kMeans, 3), 3);
    EXPECT_EQ(groupWidth(kRotations, 3), 4);
    EXPECT_EQ(groupWidth(kLogScales, 3), 3);
    EXPECT_EQ(groupWidth(kOpacityLogits, 3), 1);
    EXPECT_EQ(groupWidth(kColours, 1), 1);
    EXPECT_EQ(groupWidth(kColours, 3), 3);
    EXPECT_EQ(std::string(groupName(kMeans)), "means");
    EXPECT_EQ(std::string(groupName(kColours)), "colours");
}

TEST(GaussianParameters, ConstructorSizesEveryGroupAndZeroes) {
    const GaussianParameters params(5, 3);
    EXPECT_EQ(params.count(), 5u);
    EXPECT_EQ(params.channels, 3);
    for (int g = 0; g < kGroupCount; ++g) {
        EXPECT_EQ(params.values[g].size(), 5u * std::size_t(groupWidth(ParameterGroup(g), 3)));
        for (float v : params.values[g]) EXPECT_EQ(v, 0.0f);
    }
    EXPECT_EQ(GaussianParameters().count(), 0u);
}

TEST(GaussianParameters, AtAddressesGaussianAfterGaussian) {
    GaussianParameters params(3, 3);
    params.at(kColours, 2)[1] = 7.0f;
    params.at(kRotations, 1)[3] = 5.0f;
    EXPECT_EQ(params.values[kColours][2 * 3 + 1], 7.0f);
    EXPECT_EQ(params.values[kRotations][1 * 4 + 3], 5.0f);
}

TEST(GaussianParameters, KeepOnlyCompactsEveryGroupInOrder) {
    GaussianParameters params = tagged(5, 3);
    params.keepOnly({true, false, false, true, true});
    ASSERT_EQ(params.count(), 3u);
    for (int g = 0; g < kGroupCount; ++g)
        EXPECT_EQ(params.values[g].size(), 3u * std::size_t(params.width(ParameterGroup(g))));
    expectTag(params, 0, 0);
    expectTag(params, 1, 3);
    expectTag(params, 2, 4);
}

TEST(GaussianParameters, KeepOnlyNoneLeavesNothing) {
    GaussianParameters params = tagged(3, 1);
    params.keepOnly({false, false, false});
    EXPECT_EQ(params.count(), 0u);
    for (const auto& group : params.values) EXPECT_TRUE(group.empty());
}

TEST(GaussianParameters, PermutePutsOrderKAtK) {
    GaussianParameters params = tagged(4, 3);
    params.permute({2, 0, 3, 1});
    ASSERT_EQ(params.count(), 4u);
    expectTag(params, 0, 2);
    expectTag(params, 1, 0);
    expectTag(params, 2, 3);
    expectTag(params, 3, 1);
}

TEST(GaussianParameters, PermuteByInverseRestores) {
    const GaussianParameters original = tagged(4, 1);
    GaussianParameters params = original;
    const std::vector<std::uint32_t> order{3, 1, 0, 2};
    std::vector<std::uint32_t> inverse(order.size());
    for (std::uint32_t k = 0; k < order.size(); ++k) inverse[order[k]] = k;
    params.permute(order);
    params.permute(inverse);
    for (int g = 0; g < kGroupCount; ++g) EXPECT_EQ(params.values[g], original.values[g]);
}

TEST(GaussianParameters, AppendPutsTheOthersAfter) {
    GaussianParameters params = tagged(2, 3);
    const GaussianParameters more = tagged(3, 3);
    params.append(more);
    ASSERT_EQ(params.count(), 5u);
    expectTag(params, 1, 1);
    expectTag(params, 2, 0);
    expectTag(params, 4, 2);
}

TEST(GaussianParameters, AddIsElementWise) {
    GaussianParameters params = tagged(2, 3);
    const GaussianParameters twice = tagged(2, 3);
    params.add(twice);
    EXPECT_EQ(params.at(kColours, 1)[2], 2.0f * float(100 + 40 + 2));
    EXPECT_EQ(params.at(kMeans, 1)[2], 2.0f * float(100 + 2));
    EXPECT_EQ(params.at(kOpacityLogits, 1)[0], 2.0f * float(100 + 30));
}

TEST(GaussianParameters, SetZeroKeepsTheCount) {
    GaussianParameters params = tagged(3, 3);
    params.setZero();
    EXPECT_EQ(params.count(), 3u);
    for (const auto& group : params.values) {
        for (float v : group) EXPECT_EQ(v, 0.0f);
    }
}

TEST(GaussianParameters, AllFiniteCatchesNaNAndInfinityInAnyGroup) {
    for (int g = 0; g < kGroupCount; ++g) {
        for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
            GaussianParameters params = tagged(3, 3);
            EXPECT_TRUE(params.allFinite());
            params.at(ParameterGroup(g), 2)[0] = bad;
            EXPECT_FALSE(params.allFinite()) << groupName(ParameterGroup(g));
        }
    }
    // Huge but finite values are still valid parameters.
    GaussianParameters huge(1, 1);
    huge.at(kLogScales, 0)[0] = std::numeric_limits<float>::max();
    huge.at(kMeans, 0)[0] = -std::numeric_limits<float>::max();
    EXPECT_TRUE(huge.allFinite());
}

}  // namespace
}  // namespace gvr
