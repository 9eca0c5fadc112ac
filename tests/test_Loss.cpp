// The point-by-point loss: its value by hand, its gradient against finite
// differences, and the same gradient whichever chunk a point lands in.

#include "pipeline/Loss.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

GaussianParameters twoGaussians() {
    GaussianParameters params(2, 1);
    const float means[2][3] = {{4.0f, 5.0f, 6.0f}, {6.5f, 5.0f, 5.0f}};
    for (std::size_t i = 0; i < 2; ++i) {
        for (int a = 0; a < 3; ++a) {
            params.at(kMeans, i)[a] = means[i][a];
            params.at(kLogScales, i)[a] = std::log(1.5f + 0.25f * float(a + i));
        }
        params.at(kRotations, i)[0] = 1.0f;
        params.at(kRotations, i)[1] = 0.2f * float(i);
        *params.at(kOpacityLogits, i) = 0.3f;
        params.at(kColours, i)[0] = 0.6f - 0.2f * float(i);
    }
    return params;
}

SampleSet threePoints() {
    SampleSet samples;
    samples.points = {{4.0f, 5.0f, 6.0f}, {5.0f, 5.5f, 5.5f}, {7.0f, 4.0f, 5.0f}};
    samples.targets = {0.1f, 0.5f, 0.2f};
    samples.weights = {1.0f, 2.0f, 0.5f};
    return samples;
}

TEST(Loss, IsTheWeightedSumOfSquaredResiduals) {
    const GaussianField field(twoGaussians(), 3.0f);
    const SampleSet samples = threePoints();
    double expected = 0.0;
    std::vector<std::uint32_t> hits;
    for (std::size_t s = 0; s < samples.size(); ++s) {
        float f = 0.0f;
        field.evaluate(samples.points[s].data(), &f, hits);
        expected += samples.weights[s] * (f - samples.targets[s]) * (f - samples.targets[s]);
    }
    EXPECT_GT(expected, 0.0);
    EXPECT_NEAR(weightedSquaredError(field, samples, 0.25), 0.25 * expected, 1e-7);
}

TEST(Loss, GradientMatchesFiniteDifferences) {
    const GaussianParameters params = twoGaussians();
    const SampleSet samples = threePoints();
    GradientChunks chunks;
    chunks.reset(params.count());
    const GaussianField field(params, 3.0f);
    weightedSquaredError(field, samples, 1.0, &chunks);
    GaussianParameters gradient;
    EXPECT_EQ(chunks.sumInto(field, gradient), 2u);

    const auto lossWith = [&](ParameterGroup group, std::size_t i, int k, float delta) {
        GaussianParameters moved = params;
        moved.at(group, i)[k] += delta;
        return weightedSquaredError(GaussianField(moved, 3.0f), samples, 1.0);
    };
    const float h = 1e-3f;
    for (std::size_t i = 0; i < 2; ++i) {
        for (auto [group, k] : {std::pair{kMeans, 0}, {kMeans, 2}, {kLogScales, 1}, {kRotations, 1}, {kOpacityLogits, 0}, {kColours, 0}}) {
            const double numeric = (lossWith(group, i, k, h) - lossWith(group, i, k, -h)) / (2.0 * h);
            EXPECT_NEAR(gradient.at(group, i)[k], numeric, 2e-3 * std::max(1.0, std::abs(numeric)))
                << groupName(group) << "[" << k << "] of Gaussian " << i;
        }
    }
}

}  // namespace
}  // namespace gvr
