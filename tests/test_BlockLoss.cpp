// The block kernel: the same loss and gradient as point-by-point evaluation, the
// gradient of its own loss (finite differences), and four lanes against eight.

#include "pipeline/BlockLoss.h"
#include "pipeline/FastExp.h"
#include "tests/TestHelpers.h"

#include <cmath>

namespace gvr {
namespace {

float waves(int i, int j, int k) { return 40.0f + 30.0f * std::sin(0.4f * i) * std::cos(0.3f * j + 0.2f * k); }

/// A colour volume of @a dims, each channel waves of its own.
openvdb::GridBase::Ptr colourWaves(std::array<int, 3> dims) {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    auto access = grid->getAccessor();
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                access.setValue({i, j, k},
                                openvdb::Vec3s(waves(i, j, k), 0.5f * waves(j, k, i), 20.0f + 0.3f * waves(k, i, j)));
            }
        }
    }
    grid->setName("color");
    return grid;
}

struct Volume {
    VolumeTarget target;
    BlockGrid grid;
    Volume(int channels, std::array<int, 3> dims)
        : target(channels == 1 ? test::makeGrid(dims, waves) : colourWaves(dims), "waves"),
          grid(target.box(), {{1, 1, 1}, {5, 6, 7}, {12, 3, 9}}) {}
};

/// Every block of @a grid, weight 1 and phase 0.
std::vector<SampledBlock> everyBlock(const BlockGrid& grid) {
    std::vector<SampledBlock> blocks;
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) blocks.push_back({b, 0, 1.0f});
    return blocks;
}

/// The trainable voxels of @a grid as points, weight 1 each.
SampleSet trainablePoints(const Volume& volume) {
    SampleSet set;
    const int channels = volume.target.channels();
    for (std::uint32_t b = 0; b < volume.grid.blockCount(); ++b) {
        std::int32_t mask[kBlockVoxels];
        volume.grid.trainableMask(b, mask);
        const openvdb::Coord o = volume.grid.origin(b);
        for (int offset = 0; offset < kBlockVoxels; ++offset) {
            if (!mask[offset]) continue;
            const openvdb::Coord ijk = o.offsetBy(offset >> 6, (offset >> 3) & 7, offset & 7);
            set.points.push_back({float(ijk.x()), float(ijk.y()), float(ijk.z())});
            set.weights.push_back(1.0f);
            float value[3];
            volume.target.valueAt(ijk, value);
            set.targets.insert(set.targets.end(), value, value + channels);
        }
    }
    return set;
}

GaussianParameters gradientOf(const GaussianField& field, const GaussianParameters& params, GradientChunks& chunks) {
    GaussianParameters gradient;
    chunks.sumInto(field, params, gradient);
    return gradient;
}

/// Each group's largest |a - b| against its largest |a|.
void expectClose(const GaussianParameters& a, const GaussianParameters& b, double tolerance) {
    for (int g = 0; g < kGroupCount; ++g) {
        double largest = 0.0, difference = 0.0;
        for (std::size_t k = 0; k < a.values[g].size(); ++k) {
            largest = std::max(largest, double(std::abs(a.values[g][k])));
            difference = std::max(difference, double(std::abs(a.values[g][k] - b.values[g][k])));
        }
        EXPECT_GT(largest, 0.0) << groupName(ParameterGroup(g));
        EXPECT_LE(difference, tolerance * largest) << groupName(ParameterGroup(g));
    }
}

class BlockPath : public ::testing::TestWithParam<int> {};

TEST_P(BlockPath, GivesTheLossAndGradientOfPointEvaluation) {
    const int channels = GetParam();
    const Volume volume(channels, {21, 19, 18});
    const GaussianParameters params = test::randomGaussians(40, channels, 20.0f, 3);
    const GaussianField field(params, 3.0f);
    BlockBins bins(volume.grid, 0.0f, 0.0f);
    bins.build(field);
    BlockLossSettings settings;
    settings.scale = 0.25;
    GradientChunks blockChunks, pointChunks;
    blockChunks.reset(40);
    pointChunks.reset(40);
    const double block = blockSquaredError(field, bins, volume.target, everyBlock(volume.grid), settings, &blockChunks);
    const SampleSet points = trainablePoints(volume);
    ASSERT_EQ(points.size(), volume.grid.trainableVoxels());
    const double point = weightedSquaredError(field, points, 0.25, &pointChunks);
    EXPECT_NEAR(block, point, 1e-5 * point);
    expectClose(gradientOf(field, params, blockChunks), gradientOf(field, params, pointChunks), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(GreyAndColour, BlockPath, ::testing::Values(1, 3));

TEST(BlockLoss, SubLatticeRowsAreTheRowsOfTheirPhase) {
    const Volume volume(1, {16, 16, 16});
    const GaussianField field(test::randomGaussians(30, 1, 16.0f, 9), 3.0f);
    BlockBins bins(volume.grid, 0.0f, 0.0f);
    bins.build(field);
    BlockLossSettings settings;
    settings.rowStride = 3;
    double phases = 0.0;
    for (std::uint32_t phase = 0; phase < 3; ++phase) {
        std::vector<SampledBlock> blocks = everyBlock(volume.grid);
        for (SampledBlock& b : blocks) b.rowPhase = phase;
        phases += blockSquaredError(field, bins, volume.target, blocks, settings);
    }
    settings.rowStride = 1;
    EXPECT_NEAR(phases, blockSquaredError(field, bins, volume.target, everyBlock(volume.grid), settings),
                1e-6 * phases);
}

TEST(BlockLoss, GradientMatchesFiniteDifferences) {
    // A wide cutoff, so that no voxel crosses it between the two sides of a difference.
    const Volume volume(1, {16, 14, 12});
    GaussianParameters params = test::randomGaussians(6, 1, 12.0f, 21);
    for (float& s : params.values[kLogScales]) s = std::min(s, std::log(2.0f));
    const auto loss = [&](const GaussianParameters& p, GradientChunks* chunks) {
        const GaussianField field(p, 10.0f);
        BlockBins bins(volume.grid, 0.0f, 0.0f);
        bins.build(field);
        BlockLossSettings settings;
        settings.scale = 1e-3;
        settings.rowStride = 2;
        std::vector<SampledBlock> blocks = everyBlock(volume.grid);
        for (SampledBlock& b : blocks) b.rowPhase = 1;
        return blockSquaredError(field, bins, volume.target, blocks, settings, chunks);
    };
    GradientChunks chunks;
    chunks.reset(params.count());
    loss(params, &chunks);
    const GaussianParameters gradient = gradientOf(GaussianField(params, 10.0f), params, chunks);
    for (int g = 0; g < kGroupCount; ++g) {
        for (std::size_t k = 0; k < params.values[g].size(); ++k) {
            const float h = 1e-2f;
            GaussianParameters plus = params, minus = params;
            plus.values[g][k] += h;
            minus.values[g][k] -= h;
            const double numeric =
                (loss(plus, nullptr) - loss(minus, nullptr)) / (plus.values[g][k] - minus.values[g][k]);
            const double analytic = gradient.values[g][k];
            EXPECT_NEAR(analytic, numeric, 2e-2 * std::abs(numeric) + 1e-6) << groupName(ParameterGroup(g)) << " " << k;
        }
    }
}

TEST(BlockLoss, EightLanesAgreeWithFour) {
    if (!processorHasAvx2Fma()) GTEST_SKIP() << "no AVX2 and FMA on this processor: both kernels are the four-lane one";
    const Volume volume(3, {23, 17, 20});
    const GaussianParameters params = test::randomGaussians(50, 3, 20.0f, 13);
    const GaussianField field(params, 3.0f);
    BlockBins bins(volume.grid, 0.0f, 0.0f);
    bins.build(field);
    BlockLossSettings settings;
    settings.rowStride = 2;
    GradientChunks eight, four;
    eight.reset(50);
    four.reset(50);
    const double eightLanes = blockSquaredError(field, bins, volume.target, everyBlock(volume.grid), settings, &eight);
    settings.kernel = BlockKernel::FourLanes;
    const double fourLanes = blockSquaredError(field, bins, volume.target, everyBlock(volume.grid), settings, &four);
    // Fused multiply-adds round once where the four lanes round twice: float
    // rounding apart, not an algorithm apart.
    EXPECT_NEAR(eightLanes, fourLanes, 1e-6 * fourLanes);
    EXPECT_NE(eightLanes, 0.0);
    expectClose(gradientOf(field, params, eight), gradientOf(field, params, four), 1e-5);
}

}  // namespace
}  // namespace gvr
