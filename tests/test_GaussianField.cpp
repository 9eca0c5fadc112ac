// The Gaussian field: its value where the closed form says, nothing beyond the
// cutoff, finite values for degenerate shapes, and when its BVH must be rebuilt.

#include "pipeline/GaussianField.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace gvr {
namespace {

/// One grey Gaussian at @a mean, axis-aligned, standard deviations @a sigma, opacity
/// 1/2 and colour 0.8: a peak of 0.4.
GaussianParameters oneGaussian(std::array<float, 3> mean, std::array<float, 3> sigma) {
    GaussianParameters params(1, 1);
    for (int a = 0; a < 3; ++a) {
        params.at(kMeans, 0)[a] = mean[a];
        params.at(kLogScales, 0)[a] = std::log(sigma[a]);
    }
    params.at(kRotations, 0)[0] = 1.0f;
    *params.at(kOpacityLogits, 0) = 0.0f;
    params.at(kColours, 0)[0] = 0.8f;
    return params;
}

float valueAt(const GaussianField& field, std::array<float, 3> x) {
    std::vector<std::uint32_t> hits;
    float value = -1.0f;
    field.evaluate(x.data(), &value, hits);
    return value;
}

TEST(GaussianField, ValuesFollowTheClosedFormAndStopAtTheCutoff) {
    const GaussianField field(oneGaussian({5, 5, 5}, {2, 1, 4}), 3.0f);
    EXPECT_FLOAT_EQ(valueAt(field, {5, 5, 5}), 0.4f);
    EXPECT_NEAR(valueAt(field, {7, 5, 5}), 0.4 * std::exp(-0.5), 1e-6);                // one sigma along x
    EXPECT_NEAR(valueAt(field, {5, 6, 9}), 0.4 * std::exp(-0.5 * (1.0 + 1.0)), 1e-6);  // one along y and z
    EXPECT_GT(valueAt(field, {5, 5, 16.9f}), 0.0f);                                    // 2.98 sigma along z
    EXPECT_EQ(valueAt(field, {5, 5, 17.1f}), 0.0f);                                    // 3.03 sigma: cut
    EXPECT_EQ(valueAt(field, {11.1f, 5, 5}), 0.0f);
}

TEST(GaussianField, ANeedleThinGaussianStaysFinite) {
    // Log-scales are clamped in activation, so a collapsed axis has a finite variance.
    const GaussianField field(oneGaussian({3, 3, 3}, {1e-12f, 1, 1}), 3.0f);
    const float atMean = valueAt(field, {3, 3, 3});
    EXPECT_TRUE(std::isfinite(atMean));
    EXPECT_FLOAT_EQ(atMean, 0.4f);
    EXPECT_EQ(valueAt(field, {3.5f, 3, 3}), 0.0f);
    for (float s : field.gaussians()[0].invVariance) EXPECT_TRUE(std::isfinite(s));
}

TEST(GaussianField, AMoveWithinTheSlackKeepsTheBvhAndALargerOneDoesNot) {
    GaussianParameters params = oneGaussian({10, 10, 10}, {1, 1, 1});
    GaussianField field;
    field.rebuild(params, 3.0f, false, /*slackVoxels=*/1.0f);
    params.at(kMeans, 0)[0] += 0.5f;
    EXPECT_TRUE(field.update(params));
    EXPECT_FLOAT_EQ(valueAt(field, {10.5f, 10, 10}), 0.4f);  // the moved Gaussian is what is evaluated
    params.at(kMeans, 0)[0] += 2.0f;
    EXPECT_FALSE(field.update(params));
    GaussianParameters two = oneGaussian({10, 10, 10}, {1, 1, 1});
    two.append(oneGaussian({20, 10, 10}, {1, 1, 1}));
    EXPECT_FALSE(field.update(two));  // another count
}

TEST(GaussianField, AReleasedBvhIsNeverQueriedSilently) {
    GaussianField field(oneGaussian({5, 5, 5}, {1, 1, 1}), 3.0f);
    field.releaseBvh();
    EXPECT_THROW(valueAt(field, {5, 5, 5}), std::logic_error);  // not a silent 0
    EXPECT_THROW(field.bvh(), std::logic_error);
    EXPECT_EQ(field.gaussians().size(), 1u);  // the activated Gaussians stay
    field.rebuild(oneGaussian({5, 5, 5}, {1, 1, 1}), 3.0f);
    EXPECT_FLOAT_EQ(valueAt(field, {5, 5, 5}), 0.4f);
}

}  // namespace
}  // namespace gvr
