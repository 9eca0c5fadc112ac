// Seeding: one isotropic Gaussian per distinct active voxel, never more than the
// active voxels, reproducible from its seed.

#include "pipeline/Initialisation.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <vector>

namespace gvr {
namespace {

/// A ball of radius 10 about (10, 8, 6), zero (inactive, being the minimum) outside.
float ball(int i, int j, int k) {
    const float r2 = float((i - 10) * (i - 10) + (j - 8) * (j - 8) + (k - 6) * (k - 6));
    return std::max(0.0f, 100.0f - r2);
}

TEST(Initialisation, SeedsSitOnDistinctActiveVoxelsAsIsotropicGaussians) {
    const VolumeTarget target(test::makeGrid({20, 16, 12}, ball), "ball");
    ASSERT_GT(target.activeVoxelCount(), 1000u);
    const GaussianParameters params = initialiseGaussians(target, {60, 0.6, 0.4, 1});
    ASSERT_EQ(params.count(), 60u);
    EXPECT_TRUE(params.allFinite());
    std::set<std::tuple<int, int, int>> seen;
    for (std::size_t i = 0; i < params.count(); ++i) {
        SCOPED_TRACE(i);
        const float* mean = params.at(kMeans, i);
        for (int a = 0; a < 3; ++a) EXPECT_EQ(mean[a], std::round(mean[a]));
        const openvdb::Coord ijk{int(mean[0]), int(mean[1]), int(mean[2])};
        EXPECT_TRUE(target.isActive(ijk));
        EXPECT_GT(ball(ijk.x(), ijk.y(), ijk.z()), 0.0f);
        EXPECT_TRUE(seen.insert(std::make_tuple(ijk.x(), ijk.y(), ijk.z())).second) << "two Gaussians on one voxel";

        const float* rotation = params.at(kRotations, i);
        EXPECT_EQ(rotation[0], 1.0f);
        EXPECT_EQ(rotation[1], 0.0f);
        EXPECT_EQ(rotation[2], 0.0f);
        EXPECT_EQ(rotation[3], 0.0f);
        const float* logScale = params.at(kLogScales, i);
        EXPECT_EQ(logScale[0], logScale[1]);
        EXPECT_EQ(logScale[0], logScale[2]);
        // Sigmas are clamped to [0.5, 64] voxels.
        EXPECT_GE(logScale[0], std::log(0.5f) - 1e-6f);
        EXPECT_LE(logScale[0], std::log(64.0f) + 1e-6f);
        EXPECT_EQ(*params.at(kOpacityLogits, i), 0.0f);  // opacity 1/2
        // Positive data above a zero background: positive colours.
        EXPECT_GT(*params.at(kColours, i), 0.0f);
    }
}

TEST(Initialisation, NeverMoreGaussiansThanActiveVoxels) {
    // Five active voxels; a hundred asked for.
    const VolumeTarget target(
        test::makeGrid({8, 8, 8},
                       [](int i, int j, int k) { return (j == 3 && k == 4 && i < 5) ? float(i + 1) : 0.0f; }),
        "five voxels");
    ASSERT_EQ(target.activeVoxelCount(), 5u);
    const GaussianParameters params = initialiseGaussians(target, {100, 0.6, 0.4, 3});
    ASSERT_EQ(params.count(), 5u);
    std::set<int> columns;
    for (std::size_t i = 0; i < params.count(); ++i) {
        EXPECT_EQ(params.at(kMeans, i)[1], 3.0f);
        EXPECT_EQ(params.at(kMeans, i)[2], 4.0f);
        columns.insert(int(params.at(kMeans, i)[0]));
    }
    EXPECT_EQ(columns, (std::set<int>{0, 1, 2, 3, 4}));
}

TEST(Initialisation, ZeroCountOrEmptyVolumeGivesNone) {
    const VolumeTarget target(test::makeGrid({12, 12, 12}, ball), "ball");
    EXPECT_EQ(initialiseGaussians(target, {0, 0.6, 0.4, 1}).count(), 0u);
    const VolumeTarget empty(test::makeGrid({8, 8, 8}, [](int, int, int) { return 0.0f; }), "zeros");
    EXPECT_EQ(initialiseGaussians(empty, {50, 0.6, 0.4, 1}).count(), 0u);
}

TEST(Initialisation, BothSharesZeroStillSeedsTheCount) {
    // Nothing to renormalise: every seed is then a uniform one.
    const VolumeTarget target(test::makeGrid({20, 16, 12}, ball), "ball");
    const GaussianParameters params = initialiseGaussians(target, {30, 0.0, 0.0, 1});
    EXPECT_EQ(params.count(), 30u);
    EXPECT_TRUE(params.allFinite());
}

TEST(Initialisation, TheSeedDecides) {
    const VolumeTarget target(test::makeGrid({20, 16, 12}, ball), "ball");
    const GaussianParameters a = initialiseGaussians(target, {40, 0.0, 1.0, 5});
    const GaussianParameters again = initialiseGaussians(target, {40, 0.0, 1.0, 5});
    const GaussianParameters other = initialiseGaussians(target, {40, 0.0, 1.0, 6});
    for (int g = 0; g < kGroupCount; ++g) EXPECT_EQ(a.values[g], again.values[g]) << groupName(ParameterGroup(g));
    EXPECT_NE(a.values[kMeans], other.values[kMeans]);
}

TEST(Initialisation, ProgressEndsAtOneAndStaysInRange) {
    const VolumeTarget target(test::makeGrid({20, 16, 12}, ball), "ball");
    std::vector<double> reported;
    initialiseGaussians(target, {20, 0.6, 0.4, 1}, [&](double fraction) { reported.push_back(fraction); });
    ASSERT_FALSE(reported.empty());
    EXPECT_EQ(reported.back(), 1.0);
    for (double fraction : reported) {
        EXPECT_GE(fraction, 0.0);
        EXPECT_LE(fraction, 1.0);
    }
}

}  // namespace
}  // namespace gvr
