// The render volumes: a Gaussian field sampled on a lattice in physical units, its
// widening of thin Gaussians at constant mass, and grids sampled trilinearly.

#include "pipeline/Error.h"
#include "pipeline/Trilinear.h"
#include "render/RenderVolume.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>
#include <set>
#include <string>

namespace gvr {
namespace {

using openvdb::Coord;

constexpr int kSide = 16;

/// One grey Gaussian at the voxel (8, 8, 8), opacity 1/2, round with standard deviation @a sigma.
GaussianParameters oneGaussian(float sigma, float colour) {
    GaussianParameters params(1, 1);
    for (int a = 0; a < 3; ++a) params.at(kMeans, 0)[a] = 8.0f;
    params.at(kRotations, 0)[0] = 1.0f;
    for (int a = 0; a < 3; ++a) params.at(kLogScales, 0)[a] = std::log(sigma);
    *params.at(kOpacityLogits, 0) = 0.0f;
    params.at(kColours, 0)[0] = colour;
    return params;
}

GaussianRenderVolume volumeOf(const GaussianParameters& params, const ValueMapping& mapping, float minScale) {
    return GaussianRenderVolume(params, kDefaultCutoffSigmas, openvdb::math::Mat4d::identity(),
                                openvdb::Vec3i(kSide, kSide, kSide), mapping, 1.0, 0.0, minScale);
}

/// The block at (8, 8, 8) on the volume's own lattice, every block visible.
std::vector<float> blockAtTheMean(const RenderVolume& volume) {
    const Lattice lattice = sourceLattice(volume.worldFromIndex(), openvdb::Vec3i(kSide, kSide, kSide));
    const auto blocks = volume.blocksOn(lattice, -1e30);
    std::vector<float> values(kBlockVoxels * std::size_t(volume.channels()));
    blocks->sampleBlock(Coord(8, 8, 8), values.data());
    return values;
}

TEST(GaussianRenderVolume, SamplesTheMappedFieldAndTheBackgroundBeyondTheCutoff) {
    ValueMapping mapping;
    mapping.offset = {100.0, 0.0, 0.0};
    mapping.scale = 2.0;
    const GaussianRenderVolume volume = volumeOf(oneGaussian(2.0f, 0.8f), mapping, 0.0f);
    const std::vector<float> block = blockAtTheMean(volume);
    const float peak = 2.0f * 0.5f * 0.8f;  // scale * opacity * colour
    EXPECT_NEAR(block[blockOffset(Coord(8, 8, 8))], 100.0f + peak, 1e-4f);
    // Two voxels along x is one standard deviation: q = 1.
    EXPECT_NEAR(block[blockOffset(Coord(10, 8, 8))], 100.0f + peak * std::exp(-0.5f), 1e-4f);
    // (15, 15, 15) lies at q = 3 * 49 / 4, beyond the cutoff of 3 sigmas: the background, exactly.
    EXPECT_EQ(block[blockOffset(Coord(15, 15, 15))], 100.0f);
    EXPECT_EQ(volume.backgroundKey(), 100.0);
}

// An asset is drawn as its export holds it: between voxels, the interpolation of
// the field's values at them, not the Gaussians themselves.
TEST(GaussianRenderVolume, BetweenVoxelsItIsTheInterpolationOfItsVoxels) {
    const GaussianRenderVolume volume = volumeOf(oneGaussian(0.6f, 1.0f), ValueMapping{}, 0.0f);
    const float peak = 0.5f, oneVoxelOff = peak * std::exp(-0.5f / (0.6f * 0.6f));
    // The source's lattice moved half a voxel along x: its samples lie midway between voxels.
    Lattice midway = sourceLattice(volume.worldFromIndex(), openvdb::Vec3i(kSide, kSide, kSide));
    midway.worldFromIndex.setTranslation(openvdb::Vec3d(0.5, 0.0, 0.0));
    const auto first = volume.blocksOn(midway, -1e30);
    EXPECT_EQ(first->gaussiansReaching(), 1u);  // this build evaluated the voxels
    std::vector<float> values(kBlockVoxels);
    first->sampleBlock(Coord(8, 8, 8), values.data());
    EXPECT_NEAR(values[blockOffset(Coord(8, 8, 8))], 0.5f * (peak + oneVoxelOff), 1e-5f);
    // The Gaussian itself, half a voxel from its mean, is a good deal brighter.
    EXPECT_GT(peak * std::exp(-0.5f * 0.25f / (0.6f * 0.6f)), 0.5f * (peak + oneVoxelOff) + 0.03f);
    EXPECT_EQ(volume.blocksOn(midway, -1e30)->gaussiansReaching(), 0u);  // kept, not evaluated again
}

// A coarse first image must not wait for every voxel: a preview samples the
// Gaussians themselves, and leaves the voxels to the build that needs them.
TEST(GaussianRenderVolume, APreviewSamplesTheGaussiansWithoutEvaluatingTheVoxels) {
    const GaussianRenderVolume volume = volumeOf(oneGaussian(0.6f, 1.0f), ValueMapping{}, 0.0f);
    Lattice midway = sourceLattice(volume.worldFromIndex(), openvdb::Vec3i(kSide, kSide, kSide));
    midway.worldFromIndex.setTranslation(openvdb::Vec3d(0.5, 0.0, 0.0));
    std::vector<float> values(kBlockVoxels);
    volume.previewBlocksOn(midway, -1e30)->sampleBlock(Coord(8, 8, 8), values.data());
    EXPECT_NEAR(values[blockOffset(Coord(8, 8, 8))], 0.5f * std::exp(-0.5f * 0.25f / (0.6f * 0.6f)), 1e-5f);
    EXPECT_EQ(volume.blocksOn(midway, -1e30)->gaussiansReaching(), 1u);  // the voxels were still to evaluate
}

TEST(GaussianRenderVolume, StatisticsGatheredOnAllCoresAreThoseOfOneAndAreKept) {
    GaussianParameters params(24, 1);
    for (std::size_t i = 0; i < params.count(); ++i) {
        for (int a = 0; a < 3; ++a) params.at(kMeans, i)[a] = float((i * (3 + 2 * a)) % kSide);
        params.at(kRotations, i)[0] = 1.0f;
        for (int a = 0; a < 3; ++a) params.at(kLogScales, i)[a] = std::log(1.0f + 0.1f * float(i % 5));
        params.at(kColours, i)[0] = 0.1f + 0.03f * float(i);
    }
    const GaussianRenderVolume shared = volumeOf(params, ValueMapping{}, 0.0f),
                               alone = volumeOf(params, ValueMapping{}, 0.0f);
    VolumeStatistics oneCore;
    tbb::task_arena(1).execute([&] { oneCore = alone.statistics(); });
    const VolumeStatistics& allCores = shared.statistics();
    ASSERT_GT(allCores.values.size(), 100u);
    EXPECT_EQ(allCores.values, oneCore.values);
    EXPECT_EQ(allCores.background, oneCore.background);
    EXPECT_EQ(&shared.statistics(), &allCores);  // gathered once
}

TEST(GaussianRenderVolume, WidensThinGaussiansAndKeepsTheirMass) {
    const ValueMapping identity;
    const float thin = 0.25f, floor = 0.5f;
    const std::vector<float> widened = blockAtTheMean(volumeOf(oneGaussian(thin, 1.0f), identity, floor));
    const std::vector<float> kept = blockAtTheMean(volumeOf(oneGaussian(thin, 1.0f), identity, 0.0f));
    // Sigma doubled on three axes: the peak falls by 2^3, so peak * sigma^3 stays.
    EXPECT_NEAR(widened[blockOffset(Coord(8, 8, 8))], 0.5f / 8.0f, 1e-6f);
    EXPECT_NEAR(kept[blockOffset(Coord(8, 8, 8))], 0.5f, 1e-6f);
    // One voxel away the thin Gaussian is at q = 16 (cut); the widened one at q = 4.
    EXPECT_EQ(kept[blockOffset(Coord(9, 8, 8))], 0.0f);
    EXPECT_NEAR(widened[blockOffset(Coord(9, 8, 8))], 0.5f / 8.0f * std::exp(-2.0f), 1e-6f);
}

TEST(GridRenderVolume, SamplesTrilinearlyBetweenVoxelCentres) {
    openvdb::FloatGrid grid(0.0f);
    auto accessor = grid.getAccessor();
    accessor.setValue(Coord(1, 0, 0), 2.0f);
    accessor.setValue(Coord(1, 1, 0), 4.0f);
    float out[1];
    GridRenderVolume::trilinear(grid.getConstAccessor(), openvdb::Vec3d(0.25, 0.0, 0.0), out);
    EXPECT_FLOAT_EQ(out[0], 0.5f);
    GridRenderVolume::trilinear(grid.getConstAccessor(), openvdb::Vec3d(1.0, 0.5, 0.0), out);
    EXPECT_FLOAT_EQ(out[0], 3.0f);

    openvdb::Vec3SGrid colour(openvdb::Vec3s(0.0f));
    colour.getAccessor().setValue(Coord(0, 0, 1), openvdb::Vec3s(1.0f, 2.0f, 4.0f));
    float rgb[3];
    GridRenderVolume::trilinear(colour.getConstAccessor(), openvdb::Vec3d(0.0, 0.0, 0.5), rgb);
    EXPECT_FLOAT_EQ(rgb[0], 0.5f);
    EXPECT_FLOAT_EQ(rgb[1], 1.0f);
    EXPECT_FLOAT_EQ(rgb[2], 2.0f);
}

// The sampler reads a leaf's array when the eight corners share a leaf, the tree
// otherwise, and a tile's one value: all three must interpolate alike.
TEST(GridRenderVolume, SamplesAlikeInsideLeavesAcrossThemAndInTiles) {
    openvdb::FloatGrid grid(-1000.0f);
    auto accessor = grid.getAccessor();
    for (int i = 0; i < 16; ++i) {
        for (int j = 0; j < 16; ++j) {
            for (int k = 0; k < 16; ++k) {
                accessor.setValue(Coord(i, j, k), float((i * 31 + j * 17 + k * 7) % 23) - 11.0f);
            }
        }
    }
    grid.tree().fill(openvdb::CoordBBox(Coord(16, 0, 0), Coord(31, 15, 15)), 40.0f);  // whole leaves: tiles
    ASSERT_GT(grid.tree().activeTileCount(), 0u);
    const auto reader = grid.getConstAccessor();
    int inLeaf = 0, across = 0, inTile = 0;
    for (double x = -0.75; x < 31.0; x += 0.625) {
        for (double y = 0.3; y < 15.0; y += 1.7) {
            for (double z = 0.1; z < 15.0; z += 2.3) {
                const openvdb::Vec3d p(x, y, z);
                double expected = 0.0;
                forEachTrilinearCorner(p, [&](const Coord& c, double w) { expected += w * reader.getValue(c); });
                float out[1];
                GridRenderVolume::trilinear(reader, p, out);
                EXPECT_NEAR(out[0], expected, 1e-4) << p;
                const Coord base(int(std::floor(x)), int(std::floor(y)), int(std::floor(z)));
                const bool oneLeaf = (base.x() & 7) != 7 && (base.y() & 7) != 7 && (base.z() & 7) != 7;
                if (!oneLeaf)
                    ++across;
                else if (base.x() >= 16)
                    ++inTile;
                else
                    ++inLeaf;
            }
        }
    }
    EXPECT_GT(inLeaf, 100);
    EXPECT_GT(across, 100);
    EXPECT_GT(inTile, 10);
}

// A stack samples only the blocks where something could be seen, or whose lattice
// neighbours could be: resampling reads neighbours, so those must hold true values.
TEST(GridRenderVolume, BlocksThatCannotBeSeenAreLeftOutWithTheirNeighboursKept) {
    const auto value = [](int i, int j, int k) {
        // Its last voxels along z, 39, lie just before the lattice's slice 24 (at z = 40.8),
        // the first of a block: that block holds no visible sample, only neighbours of them.
        const bool bright = i >= 28 && i < 40 && j >= 18 && j < 30 && k >= 20 && k < 40;
        return bright ? 900.0f : 100.0f + float((i + j + k) % 7);
    };
    const GridRenderVolume volume(test::makeGrid({64, 48, 56}, value));
    // A lattice turned and coarser than the voxels, as a view stack's of a small
    // image is: a neighbour's trilinear corners need not reach what it is next to.
    Lattice lattice;
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m.preRotate(openvdb::math::Z_AXIS, 0.4);
    m.preScale(openvdb::Vec3d(1.7));
    m.setTranslation(openvdb::Vec3d(20.0, -15.0, 0.0));
    lattice.worldFromIndex = m;
    lattice.box = openvdb::CoordBBox(Coord(0), Coord(47, 47, 47));
    const auto all = volume.blocksOn(lattice, 50.0)->occupiedBlocks();
    const auto blocks = volume.blocksOn(lattice, 500.0);
    const std::vector<Coord> kept = blocks->occupiedBlocks();
    EXPECT_LT(kept.size() * 10, all.size());
    EXPECT_GT(kept.size(), 0u);
    const std::set<Coord> keptSet(kept.begin(), kept.end());
    const auto accessor = dynamic_cast<const openvdb::FloatGrid&>(volume.voxels()).getConstAccessor();
    int visible = 0;
    for (auto ijk = lattice.box.begin(); ijk; ++ijk) {
        float sample[1];
        const openvdb::Vec3d x = lattice.worldFromIndex.transform((*ijk).asVec3d());
        GridRenderVolume::trilinear(accessor, x, sample);
        if (sample[0] <= 500.0f) continue;
        ++visible;
        for (auto n = openvdb::CoordBBox(*ijk - Coord(1), *ijk + Coord(1)).begin(); n; ++n) {
            if (!lattice.box.isInside(*n)) continue;
            const Coord origin((*n).x() & ~7, (*n).y() & ~7, (*n).z() & ~7);
            EXPECT_EQ(keptSet.count(origin), 1u) << "the block of " << *n << ", next to a visible sample";
        }
    }
    EXPECT_GT(visible, 20);
}

// Blocks are sampled from dense bricks, along the axes when the lattice's run along
// the grid's, or from the tree when the lattice is far coarser than the voxels:
// every way must give the tree's trilinear samples, bit for bit.
TEST(GridRenderVolume, BlocksSampleAsTheTreeOnAxisTurnedAndCoarseLattices) {
    const GridRenderVolume volume(
        test::makeGrid({40, 36, 30}, [](int i, int j, int k) { return float((i * 13 + j * 7 + k * 3) % 17) - 4.5f; }));
    const auto accessor = dynamic_cast<const openvdb::FloatGrid&>(volume.voxels()).getConstAccessor();
    openvdb::math::Mat4d alongAxes = openvdb::math::Mat4d::zero();  // lattice x, y, z along grid y, z, x
    alongAxes(0, 1) = 0.8;
    alongAxes(1, 2) = 0.7;
    alongAxes(2, 0) = 1.0;
    alongAxes(3, 0) = -2.0;
    alongAxes(3, 1) = 1.3;
    alongAxes(3, 2) = -0.6;
    alongAxes(3, 3) = 1.0;
    openvdb::math::Mat4d turned = openvdb::math::Mat4d::identity();
    turned.preRotate(openvdb::math::Z_AXIS, 0.4);
    turned.preScale(openvdb::Vec3d(0.9));
    turned.setTranslation(openvdb::Vec3d(8.0, -5.0, 1.5));
    openvdb::math::Mat4d coarse = turned;
    coarse.preScale(openvdb::Vec3d(6.0));
    for (const auto& m : {alongAxes, turned, coarse}) {
        const Lattice lattice{m * volume.worldFromIndex(), openvdb::CoordBBox(Coord(0), Coord(44, 41, 37))};
        const auto blocks = volume.blocksOn(lattice, -1e30);
        int compared = 0;
        for (const Coord& origin : blocks->occupiedBlocks()) {
            float values[kBlockVoxels];
            const openvdb::CoordBBox voxels = blocks->sampleBlock(origin, values);
            for (auto ijk = voxels.begin(); ijk; ++ijk) {
                float expected;
                GridRenderVolume::trilinear(accessor, m.transform((*ijk).asVec3d()), &expected);
                ASSERT_EQ(std::memcmp(&expected, &values[blockOffset(*ijk)], sizeof expected), 0)
                    << *ijk << ": " << expected << " against " << values[blockOffset(*ijk)];
                ++compared;
            }
        }
        EXPECT_EQ(compared, 45 * 42 * 38);
    }
}

// Values at the ends of the float range and below its normal numbers: samples stay
// finite and between their corners, and skipping still finds the one that can be seen.
TEST(GridRenderVolume, ExtremeValuesInterpolateAndAreFoundBySkipping) {
    openvdb::FloatGrid grid(0.0f);
    auto accessor = grid.getAccessor();
    for (int i = 0; i < 24; ++i) accessor.setValue(Coord(i, 4, 4), 1e-45f);  // denormal
    accessor.setValue(Coord(18, 4, 4), 3e38f);
    accessor.setValue(Coord(19, 4, 4), -3e38f);
    const GridRenderVolume volume(grid.deepCopy());
    const auto reader = dynamic_cast<const openvdb::FloatGrid&>(volume.voxels()).getConstAccessor();
    float out[1];
    for (double x : {18.0, 18.25, 18.5, 18.75, 19.0}) {
        GridRenderVolume::trilinear(reader, openvdb::Vec3d(x, 4.0, 4.0), out);
        EXPECT_TRUE(std::isfinite(out[0])) << x;
        EXPECT_LE(std::abs(out[0]), 3e38f) << x;
    }
    GridRenderVolume::trilinear(reader, openvdb::Vec3d(18.5, 4.0, 4.0), out);
    EXPECT_NEAR(out[0], 0.0f, 1e32f);
    GridRenderVolume::trilinear(reader, openvdb::Vec3d(3.5, 4.0, 4.0), out);
    EXPECT_GE(out[0], 0.0f);
    EXPECT_LE(out[0], 1e-44f);
    const Lattice lattice = sourceLattice(volume.worldFromIndex(), openvdb::Vec3i(24, 8, 8));
    const std::vector<Coord> kept = volume.blocksOn(lattice, 1e38)->occupiedBlocks();
    const std::set<Coord> keptSet(kept.begin(), kept.end());
    EXPECT_EQ(keptSet.count(Coord(16, 0, 0)), 1u);  // holds 3e38
    EXPECT_EQ(keptSet.count(Coord(0, 0, 0)), 0u);   // denormals and zeros only, far from it
}

/// Every @a stride-th active value of @a grid in its value iterator's order: what
/// a grid's statistics sample, by definition.
std::vector<float> everyStridethValue(const openvdb::FloatGrid& grid, std::size_t stride) {
    std::vector<float> values;
    std::size_t n = 0;
    for (auto v = grid.cbeginValueOn(); v; ++v, ++n) {
        if (n % stride == 0) values.push_back(*v);
    }
    return values;
}

// A grid's statistics read its leaves on all cores when every active value lies in
// a leaf: the sample must be the one walk's, value for value and in order, with
// leaves holding different numbers of active voxels; with an active tile it walks.
TEST(GridRenderVolume, StatisticsSampleEveryStridethActiveValueInTheIteratorsOrder) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    auto accessor = grid->getAccessor();
    std::size_t active = 0;
    for (int i = -40; i < 50; ++i) {
        for (int j = -30; j < 45; ++j) {
            for (int k = 0; k < 40; ++k) {
                if ((i * 7 + j * 3 + k) % 5 == 0 || (i > 20 && j > 10)) continue;  // uneven leaves
                accessor.setValue(Coord(i, j, k), float(i * 1000 + j * 10 + k % 10));
                ++active;
            }
        }
    }
    const std::size_t stride = active / 50000;
    ASSERT_GE(stride, 2u);
    ASSERT_EQ(grid->tree().activeTileCount(), 0u);
    EXPECT_EQ(GridRenderVolume(grid->deepCopy()).statistics().values, everyStridethValue(*grid, stride));

    grid->tree().fill(openvdb::CoordBBox(Coord(64, 0, 0), Coord(95, 31, 31)), 7.0f);  // active tiles
    ASSERT_GT(grid->tree().activeTileCount(), 0u);
    const std::size_t withTiles = grid->activeVoxelCount() / 50000;
    EXPECT_EQ(GridRenderVolume(grid->deepCopy()).statistics().values, everyStridethValue(*grid, withTiles));
}

TEST(GridRenderVolume, RefusesOtherValueTypesNamingTheGrid) {
    openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(0);
    labels->setName("labels");
    try {
        GridRenderVolume volume(labels);
        FAIL() << "an int32 grid was accepted";
    } catch (const InputError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("labels"), std::string::npos) << message;
        EXPECT_NE(message.find("int32"), std::string::npos) << message;
    }
}

TEST(GridRenderVolume, KeepsTheGridsSpacingAndBox) {
    const GridRenderVolume volume(test::makeGrid(
        {6, 5, 4}, [](int i, int, int) { return float(i); }, openvdb::Vec3d(0.5, 1.0, 2.0)));
    EXPECT_EQ(volume.channels(), 1);
    EXPECT_DOUBLE_EQ(volume.voxelMm(), 0.5);
    EXPECT_DOUBLE_EQ(volume.worldFromIndex()[1][1], 1.0);
}

GridRenderVolume rampOn(const openvdb::Vec3d& spacingMm) {
    return GridRenderVolume(test::makeGrid(
        {4, 4, 4}, [](int i, int j, int k) { return float(i + j + k + 1); }, spacingMm));
}

TEST(RenderVolume, TheFinestStepMeetsThirtyTwoSamplesAVoxelCrossed) {
    // Equal voxels: a face every voxel along an axis, sqrt(3) of them a voxel along the diagonal.
    const GridRenderVolume equal = rampOn(openvdb::Vec3d(2.0));
    EXPECT_DOUBLE_EQ(equal.finestStepVoxels(openvdb::Vec3d(0, 3, 0)), 1.0 / 32.0);
    EXPECT_NEAR(equal.finestStepVoxels(openvdb::Vec3d(1, 1, 1)), 1.0 / (32.0 * std::sqrt(3.0)), 1e-12);
    EXPECT_LT(equal.finestStepVoxels(openvdb::Vec3d(1, 1, 1)), 0.05);  // the finest a user may ask
    // 1e-6 x 1 x 1 mm: along a 1 mm edge, 1/32 mm is 31250 of the shortest edges.
    const GridRenderVolume thin = rampOn(openvdb::Vec3d(1e-6, 1.0, 1.0));
    EXPECT_NEAR(thin.finestStepVoxels(openvdb::Vec3d(0, 1, 0)), 31250.0, 1e-6);
    EXPECT_NEAR(thin.finestStepVoxels(openvdb::Vec3d(1, 0, 0)), 1.0 / 32.0, 1e-12);
}

}  // namespace
}  // namespace gvr
