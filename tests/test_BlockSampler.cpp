// Blocks drawn by error: the weighted loss stays an unbiased estimate of the dense
// voxel MSE, and the blocks with the highest error are always drawn.

#include "pipeline/BlockLoss.h"
#include "pipeline/BlockSampler.h"
#include "pipeline/FieldAccuracy.h"
#include "tests/TestHelpers.h"

#include <cmath>

namespace gvr {
namespace {

TEST(BlockSampler, InclusionProbabilitiesAddUpToTheExpectedBlocks) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(-3, 0, 2), openvdb::Coord(60, 41, 29)));
    BlockSampler sampler(grid, {}, 2);
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) sampler.setBlockError(b, 0.001 * (b % 7));
    const double voxels = 2000.0;  // 2000 * 2 / 512 blocks, none near certainty
    double expected = 0.0;
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) expected += sampler.inclusionProbability(b, voxels);
    EXPECT_NEAR(expected, voxels * 2 / kBlockVoxels, 1e-9);
}

TEST(BlockSampler, TheHighestErrorBlocksAreAlwaysDrawn) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(63)));
    BlockSampler sampler(grid, {}, 1);
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) sampler.setBlockError(b, 1e-4);
    sampler.setBlockError(77, 50.0);
    EXPECT_EQ(sampler.inclusionProbability(77, 4096.0), 1.0);
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
        const std::vector<SampledBlock> drawn = sampler.draw(4096.0, seed);
        const bool has77 = std::any_of(drawn.begin(), drawn.end(), [](const SampledBlock& s) { return s.block == 77; });
        EXPECT_TRUE(has77) << "seed " << seed;
    }
}

/// The dense MSE of @a field over the voxels of @a target's box but @a excluded.
double denseMse(const GaussianField& field, const VolumeTarget& target, const std::vector<openvdb::Coord>& excluded) {
    double sum = 0.0;
    std::size_t count = 0;
    std::vector<std::uint32_t> hits;
    for (auto ijk = target.box().begin(); ijk; ++ijk) {
        if (std::find(excluded.begin(), excluded.end(), *ijk) != excluded.end()) continue;
        float value, expected;
        const float x[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        field.evaluate(x, &value, hits);
        target.valueAt(*ijk, &expected);
        sum += double(value - expected) * (value - expected);
        ++count;
    }
    return sum / double(count);
}

TEST(BlockSampler, TheWeightedBlockLossIsAnUnbiasedEstimateOfTheDenseMse) {
    // A blob the field only roughly matches, so that errors vary across blocks; the
    // box is no multiple of 8, and some voxels are held out.
    const auto blob = [](int i, int j, int k) {
        const float d2 = float((i - 12) * (i - 12) + (j - 10) * (j - 10) + (k - 9) * (k - 9));
        return 100.0f * std::exp(-d2 / 40.0f) + (i % 3 == 0 ? 5.0f : 0.0f);
    };
    const VolumeTarget target(test::makeGrid({27, 21, 18}, blob), "blob");
    const GaussianField field(test::randomGaussians(30, 1, 20.0f, 4), 3.0f);
    const std::vector<openvdb::Coord> excluded = {{1, 2, 3}, {20, 10, 5}, {8, 8, 8}, {26, 20, 17}};
    const BlockGrid grid(target.box(), excluded);
    BlockBins bins(grid, 0.0f, 0.0f);
    bins.build(field);
    const double dense = denseMse(field, target, excluded);

    ImportanceSettings settings;
    settings.uniformShare = 0.2;
    BlockSampler sampler(grid, settings, 2);
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) sampler.setBlockError(b, b % 4 == 0 ? 1.0 : 0.001);
    BlockLossSettings loss;
    loss.scale = 1.0 / double(grid.trainableVoxels());
    loss.rowStride = 2;

    constexpr int kDraws = 400;
    std::vector<double> estimates;
    for (int draw = 0; draw < kDraws; ++draw) {
        estimates.push_back(blockSquaredError(field, bins, target, sampler.draw(1500.0, 1000 + draw), loss));
    }
    double mean = 0.0;
    for (double e : estimates) mean += e / kDraws;
    double variance = 0.0;
    for (double e : estimates) variance += (e - mean) * (e - mean) / (kDraws - 1);
    const double standardError = std::sqrt(variance / kDraws);
    EXPECT_GT(standardError, 0.0);
    EXPECT_LT(std::abs(mean - dense), 4.0 * standardError)
        << "mean of estimates " << mean << ", dense MSE " << dense << ", standard error " << standardError;
}

TEST(BlockSampler, UniformSamplingDrawsBlocksInProportionToTheirVoxels) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(11, 7, 7)));  // a full and a half block
    ImportanceSettings uniform;
    uniform.uniformShare = 1.0;
    BlockSampler sampler(grid, uniform, 1);
    sampler.setBlockError(0, 5.0);  // no effect when lambda is 1
    EXPECT_NEAR(sampler.inclusionProbability(0, 100.0), 100.0 / kBlockVoxels * 512.0 / 768.0, 1e-12);
    EXPECT_NEAR(sampler.inclusionProbability(1, 100.0), 100.0 / kBlockVoxels * 256.0 / 768.0, 1e-12);
}

TEST(BlockSampler, FirstSampledYIsTheFirstRowOfThePhaseFromWhereItStarts) {
    for (int stride = 1; stride <= 8; ++stride) {
        for (int phase = 0; phase < stride; ++phase) {
            for (int x = 0; x < kBlockDim; ++x) {
                for (int yFrom = 0; yFrom < kBlockDim; ++yFrom) {
                    int expected = yFrom;
                    while ((x + expected) % stride != phase) ++expected;
                    EXPECT_EQ(firstSampledY(x, yFrom, stride, std::uint32_t(phase)), expected)
                        << "stride " << stride << ", phase " << phase << ", x " << x << ", from " << yFrom;
                }
            }
        }
    }
}

}  // namespace
}  // namespace gvr
