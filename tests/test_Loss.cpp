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
    EXPECT_EQ(chunks.sumInto(field, params, gradient), 2u);

    const auto lossWith = [&](ParameterGroup group, std::size_t i, int k, float delta) {
        GaussianParameters moved = params;
        moved.at(group, i)[k] += delta;
        return weightedSquaredError(GaussianField(moved, 3.0f), samples, 1.0);
    };
    const float h = 1e-3f;
    for (std::size_t i = 0; i < 2; ++i) {
        for (auto [group, k] : {std::pair{kMeans, 0},
                                {kMeans, 2},
                                {kLogScales, 1},
                                {kRotations, 1},
                                {kOpacityLogits, 0},
                                {kColours, 0}}) {
            const double numeric = (lossWith(group, i, k, h) - lossWith(group, i, k, -h)) / (2.0 * h);
            EXPECT_NEAR(gradient.at(group, i)[k], numeric, 2e-3 * std::max(1.0, std::abs(numeric)))
                << groupName(group) << "[" << k << "] of Gaussian " << i;
        }
    }
}

TEST(Loss, ChunksKeepEachGaussiansSumsAcrossPagesAndResets) {
    constexpr std::size_t kCount = 5000;  // more than two pages of sums in a chunk
    GaussianParameters params(kCount, 1);
    for (std::size_t i = 0; i < kCount; ++i) {
        params.at(kMeans, i)[0] = float(i % 40);
        params.at(kMeans, i)[1] = float(i / 40);
        params.at(kRotations, i)[0] = 1.0f;
        params.at(kRotations, i)[3] = 0.001f * float(i % 97);
        params.at(kColours, i)[0] = 0.5f;
    }
    const GaussianField field(params, 3.0f);
    const auto point = [](std::size_t i, std::size_t c, float d[3], float upstream[1]) {
        d[0] = 0.1f * float(c + 1);
        d[1] = -0.05f * float(i % 7);
        d[2] = 0.02f * float(c);
        upstream[0] = 0.001f * float(i % 13) - 0.005f;
    };
    GradientChunks chunks;
    chunks.reset(kCount);
    float d[3], upstream[1];
    for (std::size_t i = 0; i < kCount; ++i) {  // a step before, whose sums the reset must clear
        const float stale[3] = {9, 9, 9}, big[1] = {9};
        chunks.sumsOf(i % 5, std::uint32_t(i)).add(field.gaussians()[i], 1, stale, 1.0f, big);
    }
    chunks.reset(kCount);
    GaussianParameters expected(kCount, 1);
    for (std::size_t i = 0; i < kCount; ++i) {
        GradientSums total;
        for (std::size_t c : {i % 3, std::size_t(7)}) {
            point(i, c, d, upstream);
            GradientSums one;
            one.add(field.gaussians()[i], 1, d, 0.5f, upstream);
            total += one;
            chunks.sumsOf(c, std::uint32_t(i)).add(field.gaussians()[i], 1, d, 0.5f, upstream);
        }
        accumulateGradient(params, field.gaussians()[i], i, total, expected, i);
    }
    GaussianParameters gradient;
    EXPECT_EQ(chunks.sumInto(field, params, gradient), kCount);
    for (int group = 0; group < kGroupCount; ++group) {
        EXPECT_EQ(gradient.values[group], expected.values[group]) << groupName(ParameterGroup(group));
    }
}

}  // namespace
}  // namespace gvr
