// The cube-by-cube loss gives what the point-by-point loss gives on the same
// voxels, and cube draws keep the Monte Carlo estimate unbiased.

#include "ImportanceSampler.h"
#include "Loss.h"
#include "TestHelpers.h"
#include "VolumeTarget.h"

#include <cmath>
#include <random>

namespace gvr {
namespace {

/// Every voxel of the drawn cubes but the excluded ones, grouped by cube.
SampleSet cubeSet(const VolumeTarget& target, const ImportanceSampler& sampler,
                  const std::vector<BlockSample>& cubes) {
    SampleSet set;
    for (const BlockSample& cube : cubes) {
        const openvdb::Coord lo = cube.box.min(), hi = cube.box.max();
        SampleBlock block{{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}, std::uint32_t(set.size()), 0};
        for (auto ijk = cube.box.begin(); ijk; ++ijk) {
            if (sampler.isExcluded(*ijk)) continue;
            set.points.push_back({float((*ijk).x()), float((*ijk).y()), float((*ijk).z())});
            set.weights.push_back(cube.weight / float(cubes.size()));
            float value;
            target.valueAt(*ijk, &value);
            set.targets.push_back(value);
        }
        block.end = std::uint32_t(set.size());
        set.blocks.push_back(block);
    }
    return set;
}

/// A few overlapping Gaussians of random shape over a 20 x 18 x 14 box.
GaussianParameters someGaussians(int count) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    GaussianParameters params(count, 1);
    for (int i = 0; i < count; ++i) {
        const float mean[3] = {20 * unit(random), 18 * unit(random), 14 * unit(random)};
        std::copy_n(mean, 3, params.at(kMeans, i));
        for (int k = 0; k < 4; ++k) params.at(kRotations, i)[k] = unit(random) - 0.5f + (k == 0 ? 1.0f : 0.0f);
        for (int a = 0; a < 3; ++a) params.at(kLogScales, i)[a] = std::log(0.7f + 3.0f * unit(random));
        *params.at(kOpacityLogits, i) = unit(random);
        params.at(kColours, i)[0] = unit(random);
    }
    return params;
}

VolumeTarget ramp() {
    return VolumeTarget(test::makeGrid({20, 18, 14}, [](int i, int j, int k) { return float(i + 2 * j + 3 * (k % 5)); }),
                        "ramp");
}

TEST(Loss, CubeByCubeEqualsPointByPoint) {
    const VolumeTarget target = ramp();
    const GaussianParameters params = someGaussians(40);
    const GaussianField field(params, 3.0f);
    ImportanceSampler sampler(target.box(), {});
    sampler.exclude({openvdb::Coord(1, 1, 1), openvdb::Coord(5, 6, 7), openvdb::Coord(19, 17, 13)});
    for (int edge : {2, 4, 8}) {
        const SampleSet cubes = cubeSet(target, sampler, sampler.drawBlocks(30, edge, 11));
        SampleSet points = cubes;
        points.blocks.clear();

        GradientChunks cubeGradient, pointGradient;
        cubeGradient.reset(params.count());
        pointGradient.reset(params.count());
        std::vector<float> cubeResiduals, pointResiduals;
        const double cubeLoss = weightedSquaredError(field, cubes, 0.7, &cubeGradient, &cubeResiduals);
        const double pointLoss = weightedSquaredError(field, points, 0.7, &pointGradient, &pointResiduals);
        EXPECT_GT(pointLoss, 0.0);
        EXPECT_NEAR(cubeLoss, pointLoss, 1e-9 * pointLoss) << "edge " << edge;
        ASSERT_EQ(cubeResiduals.size(), pointResiduals.size());
        for (std::size_t s = 0; s < pointResiduals.size(); ++s) {
            EXPECT_NEAR(cubeResiduals[s], pointResiduals[s], 1e-6f * (1.0f + pointResiduals[s])) << "edge " << edge;
        }

        GaussianParameters a, b;
        cubeGradient.sumInto(field, a);
        pointGradient.sumInto(field, b);
        for (int g = 0; g < kGroupCount; ++g) {
            float largest = 0.0f;
            for (float v : b.values[g]) largest = std::max(largest, std::abs(v));
            EXPECT_GT(largest, 0.0f) << groupName(ParameterGroup(g));
            for (std::size_t k = 0; k < b.values[g].size(); ++k) {
                EXPECT_NEAR(a.values[g][k], b.values[g][k], 1e-4f * largest) << groupName(ParameterGroup(g)) << " " << k;
            }
        }
    }
}

TEST(Loss, CubeDrawsEstimateTheMseOverTheRemainingVoxelsUnbiasedly) {
    const VolumeTarget target = ramp();
    const GaussianField field(someGaussians(15), 3.0f);
    ImportanceSettings settings;
    settings.uniformShare = 0.2;
    ImportanceSampler sampler(target.box(), settings);
    for (std::uint32_t b = 0; b < sampler.blockCount(); ++b) sampler.setBlockError(b, b % 3 == 0 ? 1.0 : 0.01);
    std::vector<openvdb::Coord> excluded;
    for (auto ijk = target.box().begin(); ijk; ++ijk) {
        if (((*ijk).x() * 7 + (*ijk).y() * 3 + (*ijk).z()) % 11 == 0) excluded.push_back(*ijk);
    }
    sampler.exclude(excluded);

    double dense = 0.0;
    std::size_t remaining = 0;
    std::vector<std::uint32_t> hits;
    for (auto ijk = target.box().begin(); ijk; ++ijk) {
        if (sampler.isExcluded(*ijk)) continue;
        const float x[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        float value, expected;
        field.evaluate(x, &value, hits);
        target.valueAt(*ijk, &expected);
        dense += double(value - expected) * (value - expected);
        ++remaining;
    }
    dense /= double(remaining);

    for (int edge : {2, 4, 8}) {
        constexpr int kDraws = 300;
        double sum = 0.0, sumSquares = 0.0;
        for (int draw = 0; draw < kDraws; ++draw) {
            const double estimate = weightedSquaredError(field, cubeSet(target, sampler, sampler.drawBlocks(6, edge, 500 + draw)), 1.0);
            sum += estimate;
            sumSquares += estimate * estimate;
        }
        const double mean = sum / kDraws;
        const double standardError = std::sqrt((sumSquares / kDraws - mean * mean) / kDraws);
        EXPECT_GT(standardError, 0.0);
        EXPECT_LT(std::abs(mean - dense), 4.0 * standardError)
            << "edge " << edge << ": mean of estimates " << mean << ", dense " << dense << ", standard error " << standardError;
    }
    EXPECT_THROW(sampler.drawBlocks(1, 3, 1), std::invalid_argument);
}

}  // namespace
}  // namespace gvr
