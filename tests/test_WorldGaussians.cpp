// Gaussians in the world: world means, ascending scales and a unit quaternion
// that together rebuild the index covariance mapped through the voxel spacing and
// shear. Eigenvectors have arbitrary signs, so the tests compare covariances, not
// quaternions.

#include "pipeline/GaussianKernel.h"
#include "pipeline/WorldGaussians.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace gvr {
namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

/// The column-vector rotation of unit quaternion (w, x, y, z).
Mat3 rotationOf(const std::array<double, 4>& q) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    Mat3 r;
    r[0] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)};
    r[1] = {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)};
    r[2] = {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    return r;
}

/// R diag(scale^2) R^T of a world Gaussian.
Mat3 covarianceOf(const WorldGaussian& g) {
    const Mat3 r = rotationOf(g.rotation);
    Mat3 s{};
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            for (int c = 0; c < 3; ++c) s[a][b] += r[a][c] * r[b][c] * g.scale[c] * g.scale[c];
        }
    }
    return s;
}

void expectCovariance(const WorldGaussian& g, const Mat3& expected, double tolerance) {
    const Mat3 actual = covarianceOf(g);
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) EXPECT_NEAR(actual[a][b], expected[a][b], tolerance) << a << ", " << b;
    }
}

void expectUnitWithNonNegativeW(const WorldGaussian& g) {
    const auto& q = g.rotation;
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-12);
    EXPECT_GE(q[0], 0.0);
}

/// One grey Gaussian with identity rotation and amplitude 2 (opacity 1/2, colour 4).
GaussianAsset oneGaussian(const std::array<float, 3>& mean, const std::array<float, 3>& logScales) {
    GaussianAsset asset;
    asset.params = GaussianParameters(1, 1);
    std::copy(mean.begin(), mean.end(), asset.params.at(kMeans, 0));
    asset.params.at(kRotations, 0)[0] = 1.0f;
    std::copy(logScales.begin(), logScales.end(), asset.params.at(kLogScales, 0));
    *asset.params.at(kOpacityLogits, 0) = 0.0f;  // opacity 1/2
    *asset.params.at(kColours, 0) = 4.0f;
    return asset;
}

TEST(WorldGaussians, SpacingScalesAxesAndPlacesTheMean) {
    GaussianAsset asset = oneGaussian({2.0f, 4.0f, 6.0f}, {0.0f, std::log(2.0f), std::log(3.0f)});
    asset.worldFromIndex.setToScale(openvdb::Vec3d(0.5, 1.0, 2.0));
    asset.worldFromIndex.setTranslation(openvdb::Vec3d(10.0, 20.0, 30.0));
    // The background offset is not part of a Gaussian's amplitude; the scale is.
    asset.mapping.offset = {-1000.0, 0.0, 0.0};
    asset.mapping.scale = 1000.0;
    const std::vector<WorldGaussian> world = worldGaussians(asset);
    ASSERT_EQ(world.size(), 1u);
    const WorldGaussian& g = world[0];
    EXPECT_NEAR(g.mean[0], 11.0, 1e-9);
    EXPECT_NEAR(g.mean[1], 24.0, 1e-9);
    EXPECT_NEAR(g.mean[2], 42.0, 1e-9);
    // Index sigmas 1, 2, 3 times spacings 0.5, 1, 2.
    EXPECT_NEAR(g.scale[0], 0.5, 1e-5);
    EXPECT_NEAR(g.scale[1], 2.0, 1e-5);
    EXPECT_NEAR(g.scale[2], 6.0, 1e-5);
    expectUnitWithNonNegativeW(g);
    expectCovariance(g, Mat3{{{0.25, 0, 0}, {0, 4, 0}, {0, 0, 36}}}, 1e-4);
    EXPECT_NEAR(g.amplitude[0], 0.5 * 4.0 * 1000.0, 1e-3);
    EXPECT_EQ(g.amplitude[1], 0.0);  // unused channels
    EXPECT_EQ(g.amplitude[2], 0.0);
}

TEST(WorldGaussians, ScalesComeOutAscendingWhateverTheStoredOrder) {
    GaussianAsset asset = oneGaussian({0.0f, 0.0f, 0.0f}, {std::log(5.0f), std::log(1.0f), std::log(3.0f)});
    const WorldGaussian g = worldGaussians(asset).at(0);
    EXPECT_NEAR(g.scale[0], 1.0, 1e-5);
    EXPECT_NEAR(g.scale[1], 3.0, 1e-5);
    EXPECT_NEAR(g.scale[2], 5.0, 1e-5);
    expectCovariance(g, Mat3{{{25, 0, 0}, {0, 1, 0}, {0, 0, 9}}}, 1e-3);
}

TEST(WorldGaussians, ARotatedGaussianKeepsItsOrientation) {
    // 90 degrees about z: the Gaussian's first axis (sigma 1) lies along world y.
    GaussianAsset asset = oneGaussian({0.0f, 0.0f, 0.0f}, {0.0f, std::log(2.0f), std::log(3.0f)});
    const float half = std::sqrt(0.5f);
    float* q = asset.params.at(kRotations, 0);
    q[0] = half;
    q[3] = half;
    const WorldGaussian g = worldGaussians(asset).at(0);
    expectUnitWithNonNegativeW(g);
    expectCovariance(g, Mat3{{{4, 0, 0}, {0, 1, 0}, {0, 0, 9}}}, 1e-4);
}

TEST(WorldGaussians, ShearedPlacementMapsTheCovariance) {
    GaussianAsset asset;
    asset.params = test::randomGaussians(20, 1, 30.0f, 7);
    openvdb::math::Mat4d& m = asset.worldFromIndex;
    m(0, 0) = 0.8;
    m(1, 1) = 1.2;
    m(2, 2) = 2.5;
    m(1, 0) = 0.3;  // index j moves world x: a gantry-tilt shear
    m(2, 1) = -0.4;
    const std::vector<WorldGaussian> world = worldGaussians(asset);
    ASSERT_EQ(world.size(), 20u);
    for (std::size_t i = 0; i < world.size(); ++i) {
        const ActiveGaussian a = activate(asset.params, i);
        // Index covariance R S^2 R^T, carried to the world by L = M^T (M is row-vector).
        Mat3 index{};
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                for (int k = 0; k < 3; ++k)
                    index[r][c] += double(a.rotation[3 * r + k]) * a.rotation[3 * c + k] / a.invVariance[k];
            }
        }
        Mat3 expected{};
        double largest = 0.0;
        for (int p = 0; p < 3; ++p) {
            for (int q = 0; q < 3; ++q) {
                for (int r = 0; r < 3; ++r) {
                    for (int c = 0; c < 3; ++c) expected[p][q] += m(r, p) * index[r][c] * m(c, q);
                }
                largest = std::max(largest, std::abs(expected[p][q]));
            }
        }
        SCOPED_TRACE(i);
        EXPECT_LE(world[i].scale[0], world[i].scale[1]);
        EXPECT_LE(world[i].scale[1], world[i].scale[2]);
        expectUnitWithNonNegativeW(world[i]);
        expectCovariance(world[i], expected, 1e-6 * largest);
        const openvdb::Vec3d mean = m.transform(openvdb::Vec3d(a.mean[0], a.mean[1], a.mean[2]));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(world[i].mean[k], mean[k], 1e-9);
    }
}

TEST(WorldGaussians, ExtremeLogScalesAreClampedAsTheFieldClampsThem) {
    // The kernel clamps log-scales to [kMinLogScale, kMaxLogScale]; the world scales must agree.
    GaussianAsset asset = oneGaussian({0.0f, 0.0f, 0.0f}, {-50.0f, 0.0f, 50.0f});
    const WorldGaussian g = worldGaussians(asset).at(0);
    const double tiny = std::exp(double(kMinLogScale)), huge = std::exp(double(kMaxLogScale));
    EXPECT_NEAR(g.scale[0], tiny, 1e-5 * tiny);
    EXPECT_NEAR(g.scale[1], 1.0, 1e-6);
    EXPECT_NEAR(g.scale[2], huge, 1e-5 * huge);
    for (double s : g.scale) EXPECT_TRUE(std::isfinite(s));
}

TEST(WorldGaussians, AnEmptyAssetHasNone) {
    GaussianAsset asset;
    asset.params = GaussianParameters(0, 3);
    EXPECT_TRUE(worldGaussians(asset).empty());
}

}  // namespace
}  // namespace gvr
