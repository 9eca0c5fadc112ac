// The analytic adjoint of one Gaussian against central finite differences, and the
// kernel's behaviour at extreme shapes.

#include "pipeline/GaussianKernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace gvr {
namespace {

/// One Gaussian with random but well-conditioned parameters.
GaussianParameters randomGaussian(std::mt19937& random, int channels) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    GaussianParameters params(1, channels);
    for (int a = 0; a < 3; ++a) params.at(kMeans, 0)[a] = 2.0f * unit(random);
    for (int k = 0; k < 4; ++k) params.at(kRotations, 0)[k] = unit(random) + (k == 0 ? 1.5f : 0.0f);
    for (int a = 0; a < 3; ++a) params.at(kLogScales, 0)[a] = 0.4f * unit(random) + 0.5f;
    *params.at(kOpacityLogits, 0) = unit(random);
    for (int c = 0; c < channels; ++c) params.at(kColours, 0)[c] = unit(random);
    return params;
}

/// L = sum_c upstream_c f_c(x)
double objective(const GaussianParameters& params, const float x[3], const float* upstream) {
    float value[3] = {0, 0, 0};
    accumulateValue(activate(params, 0), x, 1e6f, params.channels, value);
    double sum = 0.0;
    for (int c = 0; c < params.channels; ++c) sum += double(upstream[c]) * value[c];
    return sum;
}

class KernelGradient : public ::testing::TestWithParam<int> {};

TEST_P(KernelGradient, MatchesCentralFiniteDifferences) {
    const int channels = GetParam();
    std::mt19937 random(1234 + channels);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int trial = 0; trial < 20; ++trial) {
        GaussianParameters params = randomGaussian(random, channels);
        const float x[3] = {params.at(kMeans, 0)[0] + unit(random), params.at(kMeans, 0)[1] + unit(random),
                            params.at(kMeans, 0)[2] + unit(random)};
        const float upstream[3] = {unit(random), unit(random), unit(random)};
        GaussianParameters gradient(1, channels);
        accumulateGradient(params, activate(params, 0), 0, x, 1e6f, upstream, gradient);
        for (int g = 0; g < kGroupCount; ++g) {
            for (int k = 0; k < params.width(ParameterGroup(g)); ++k) {
                const float step = 1e-3f;
                GaussianParameters plus = params, minus = params;
                plus.at(ParameterGroup(g), 0)[k] += step;
                minus.at(ParameterGroup(g), 0)[k] -= step;
                const double numeric = (objective(plus, x, upstream) - objective(minus, x, upstream)) / (2.0 * step);
                const double analytic = gradient.at(ParameterGroup(g), 0)[k];
                EXPECT_NEAR(analytic, numeric, 2e-3 + 2e-2 * std::abs(numeric))
                    << groupName(ParameterGroup(g)) << "[" << k << "], trial " << trial;
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(GreyAndRgb, KernelGradient, ::testing::Values(1, 3));

TEST_P(KernelGradient, SumsOverManyPointsMatchPointByPoint) {
    const int channels = GetParam();
    std::mt19937 random(99 + channels);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int trial = 0; trial < 20; ++trial) {
        const GaussianParameters params = randomGaussian(random, channels);
        const ActiveGaussian g = activate(params, 0);
        GaussianParameters pointByPoint(1, channels), summed(1, channels);
        GradientSums sums;
        for (int p = 0; p < 7; ++p) {
            const float x[3] = {g.mean[0] + 2 * unit(random), g.mean[1] + 2 * unit(random),
                                g.mean[2] + 2 * unit(random)};
            const float upstream[3] = {unit(random), unit(random), unit(random)};
            accumulateGradient(params, g, 0, x, 1e6f, upstream, pointByPoint);
            float u[3];
            const float q = mahalanobis2(g, x, u);
            const float d[3] = {x[0] - g.mean[0], x[1] - g.mean[1], x[2] - g.mean[2]};
            sums.add(g, channels, d, std::exp(-0.5f * q), upstream);
        }
        accumulateGradient(params, g, 0, sums, summed, 0);
        for (int group = 0; group < kGroupCount; ++group) {
            for (int k = 0; k < params.width(ParameterGroup(group)); ++k) {
                const float expected = pointByPoint.at(ParameterGroup(group), 0)[k];
                EXPECT_NEAR(summed.at(ParameterGroup(group), 0)[k], expected, 1e-5f + 1e-4f * std::abs(expected))
                    << groupName(ParameterGroup(group)) << "[" << k << "], trial " << trial;
            }
        }
    }
}

TEST(Kernel, InverseCovarianceGivesTheSameQAsTheRotatedFrame) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int trial = 0; trial < 50; ++trial) {
        const ActiveGaussian g = activate(randomGaussian(random, 1), 0);
        const float x[3] = {g.mean[0] + 3 * unit(random), g.mean[1] + 3 * unit(random), g.mean[2] + 3 * unit(random)};
        float u[3];
        const double expected = mahalanobis2(g, x, u);
        const double d[3] = {double(x[0]) - g.mean[0], double(x[1]) - g.mean[1], double(x[2]) - g.mean[2]};
        const float* G = g.inverseCovariance;
        const double q = G[0] * d[0] * d[0] + G[1] * d[1] * d[1] + G[2] * d[2] * d[2] +
                         2.0 * (G[3] * d[0] * d[1] + G[4] * d[0] * d[2] + G[5] * d[1] * d[2]);
        EXPECT_NEAR(q, expected, 1e-4 * (1.0 + expected)) << "trial " << trial;
    }
}

TEST(Kernel, TruncatesExactlyAtTheCutoff) {
    GaussianParameters params(1, 1);
    params.at(kRotations, 0)[0] = 1.0f;
    params.at(kColours, 0)[0] = 1.0f;
    const ActiveGaussian g = activate(params, 0);
    const float cutoff2 = 9.0f;
    float inside = 0.0f, outside = 0.0f;
    const float justInside[3] = {2.99f, 0, 0}, justOutside[3] = {3.01f, 0, 0};
    accumulateValue(g, justInside, cutoff2, 1, &inside);
    accumulateValue(g, justOutside, cutoff2, 1, &outside);
    EXPECT_NEAR(inside, 0.5f * std::exp(-0.5f * 2.99f * 2.99f), 1e-6f);
    EXPECT_EQ(outside, 0.0f);
    float lower[3], upper[3];
    truncatedBounds(g, 3.0f, lower, upper);
    EXPECT_NEAR(upper[0], 3.0f, 1e-6f);
    EXPECT_NEAR(lower[2], -3.0f, 1e-6f);
}

TEST(Kernel, BoundsContainTheRotatedEllipsoid) {
    std::mt19937 random(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int trial = 0; trial < 50; ++trial) {
        GaussianParameters params = randomGaussian(random, 1);
        params.at(kLogScales, 0)[0] = 2.0f;  // elongated
        const ActiveGaussian g = activate(params, 0);
        float lower[3], upper[3];
        truncatedBounds(g, 3.0f, lower, upper);
        // Points on the ellipsoid surface: mean + R S (3 * unit direction).
        for (int p = 0; p < 20; ++p) {
            float dir[3] = {unit(random), unit(random), unit(random)};
            const float norm = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            for (int a = 0; a < 3; ++a) {
                float world = g.mean[a];
                for (int b = 0; b < 3; ++b)
                    world += g.rotation[3 * a + b] * 3.0f * dir[b] / (norm * std::sqrt(g.invVariance[b]));
                EXPECT_GE(world, lower[a] - 1e-3f);
                EXPECT_LE(world, upper[a] + 1e-3f);
            }
        }
    }
}

TEST(Kernel, GradientAtNeedlesAndSheetsMatchesFiniteDifferences) {
    // Scale ratio 1e4: standard deviations of 0.01 and 100 voxels. Each point lies
    // inside one standard deviation of the thin axes, where the value is large and
    // changes fast; the finite-difference steps are small against those scales.
    struct Case {
        const char* name;
        float logScales[3];
        float offset[3];  // point minus mean (identity rotation: the Gaussian's own frame)
    };
    const Case cases[] = {{"needle", {-4.6f, -4.6f, 4.6f}, {0.005f, -0.004f, 3.0f}},
                          {"sheet", {4.6f, 4.6f, -4.6f}, {2.0f, -3.0f, 0.004f}}};
    const float steps[kGroupCount] = {1e-4f, 1e-5f, 1e-3f, 1e-3f, 1e-3f};  // means, rotations, scales, ...
    for (const Case& shape : cases) {
        GaussianParameters params(1, 1);
        for (int a = 0; a < 3; ++a) params.at(kMeans, 0)[a] = 5.0f + float(a);
        params.at(kRotations, 0)[0] = 1.0f;
        std::copy_n(shape.logScales, 3, params.at(kLogScales, 0));
        *params.at(kOpacityLogits, 0) = 0.5f;
        params.at(kColours, 0)[0] = 0.8f;
        const float x[3] = {5.0f + shape.offset[0], 6.0f + shape.offset[1], 7.0f + shape.offset[2]};
        const float upstream[1] = {1.0f};
        GaussianParameters gradient(1, 1);
        accumulateGradient(params, activate(params, 0), 0, x, 1e6f, upstream, gradient);
        ASSERT_GT(objective(params, x, upstream), 0.1) << shape.name << ": the point must sit where the value is large";
        for (int g = 0; g < kGroupCount; ++g) {
            for (int k = 0; k < params.width(ParameterGroup(g)); ++k) {
                GaussianParameters plus = params, minus = params;
                plus.at(ParameterGroup(g), 0)[k] += steps[g];
                minus.at(ParameterGroup(g), 0)[k] -= steps[g];
                const double numeric =
                    (objective(plus, x, upstream) - objective(minus, x, upstream)) / (2.0 * steps[g]);
                const double analytic = gradient.at(ParameterGroup(g), 0)[k];
                EXPECT_NEAR(analytic, numeric, 2e-3 + 2e-2 * std::abs(numeric))
                    << shape.name << ": " << groupName(ParameterGroup(g)) << "[" << k << "]";
            }
        }
    }
}

TEST(Kernel, ExtremeShapesStayFinite) {
    // Needles and sheets (scale ratio 1e4), near-singular covariances, scales far
    // below and above a voxel, and a vanished quaternion.
    const float shapes[][3] = {{-4.6f, -4.6f, 4.6f},
                               {4.6f, 4.6f, -4.6f},
                               {kMinLogScale, kMinLogScale, kMinLogScale},
                               {kMaxLogScale, kMaxLogScale, kMaxLogScale},
                               {-20.0f, 0.0f, 30.0f}};
    for (const auto& shape : shapes) {
        for (float quatScale : {1.0f, 0.0f}) {
            GaussianParameters params(1, 3);
            const float q[4] = {0.3f * quatScale, 0.5f * quatScale, -0.2f * quatScale, 0.7f * quatScale};
            std::copy_n(q, 4, params.at(kRotations, 0));
            std::copy_n(shape, 3, params.at(kLogScales, 0));
            *params.at(kOpacityLogits, 0) = 40.0f;
            for (int c = 0; c < 3; ++c) params.at(kColours, 0)[c] = 1e3f;
            const ActiveGaussian g = activate(params, 0);
            for (float offset : {0.0f, 1e-4f, 0.5f, 10.0f}) {
                const float x[3] = {offset, -offset, 0.5f * offset};
                float value[3] = {0, 0, 0};
                accumulateValue(g, x, 9.0f, 3, value);
                const float upstream[3] = {1.0f, -1.0f, 0.5f};
                GaussianParameters gradient(1, 3);
                accumulateGradient(params, g, 0, x, 9.0f, upstream, gradient);
                EXPECT_TRUE(std::isfinite(value[0]) && std::isfinite(value[1]) && std::isfinite(value[2]));
                EXPECT_TRUE(gradient.allFinite()) << "shape " << shape[0] << "," << shape[1] << "," << shape[2];
            }
        }
    }
}

}  // namespace
}  // namespace gvr
