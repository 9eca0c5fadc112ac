// A brick must sample exactly as the tree does: a stack built from bricks is the
// stack built before them, bit for bit.
#include "render/VoxelBrick.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace gvr {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

/// Values that differ voxel to voxel, leaves of them and tiles, around a negative corner.
openvdb::FloatGrid::Ptr patchwork() {
    auto grid = openvdb::FloatGrid::create(-1000.0f);
    auto accessor = grid->getAccessor();
    for (int i = -12; i < 12; ++i) {
        for (int j = -12; j < 12; ++j) {
            for (int k = -12; k < 12; ++k)
                accessor.setValue(Coord(i, j, k), float((i * 31 + j * 17 + k * 7) % 23) * 0.37f);
        }
    }
    grid->tree().fill(CoordBBox(Coord(16, -8, -8), Coord(31, 7, 7)), 40.0f);  // whole leaves: tiles
    return grid;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Every sample from @a from to below @a to, @a step apart along each axis: the
/// brick's is the tree's, bit for bit, and finite.
template <typename GridT>
void expectSamplesAsTheTree(const GridT& grid, const VoxelBrick<GridT>& brick, const openvdb::Vec3d& from,
                            const openvdb::Vec3d& to, const openvdb::Vec3d& step) {
    constexpr int channels = std::is_same_v<typename GridT::ValueType, openvdb::Vec3s> ? 3 : 1;
    const auto accessor = grid.getConstAccessor();
    for (double x = from[0]; x < to[0]; x += step[0]) {
        for (double y = from[1]; y < to[1]; y += step[1]) {
            for (double z = from[2]; z < to[2]; z += step[2]) {
                float fromTree[channels], fromBrick[channels];
                GridRenderVolume::trilinear(accessor, openvdb::Vec3d(x, y, z), fromTree);
                brick.trilinear(openvdb::Vec3d(x, y, z), fromBrick);
                for (int c = 0; c < channels; ++c) {
                    ASSERT_TRUE(std::isfinite(fromBrick[c])) << x << " " << y << " " << z;
                    ASSERT_TRUE(sameBits(fromTree[c], fromBrick[c])) << x << " " << y << " " << z;
                }
            }
        }
    }
}

TEST(VoxelBrick, SamplesAsTheTreeToTheBitInLeavesAcrossThemInTilesAndBeyond) {
    const auto grid = patchwork();
    ASSERT_GT(grid->tree().activeTileCount(), 0u);
    const auto accessor = grid->getConstAccessor();
    VoxelBrick<openvdb::FloatGrid> brick;
    const CoordBBox box(Coord(-14, -13, -12), Coord(36, 13, 14));  // reaches the background
    brick.fill(*grid, box);
    EXPECT_EQ(brick.box(), box);
    int samples = 0;
    for (double x = -13.9; x < 35.0; x += 0.61) {
        for (double y = -12.7; y < 12.0; y += 1.3) {
            for (double z = -11.2; z < 13.0; z += 0.9) {
                const openvdb::Vec3d p(x, y, z);
                float fromTree, fromBrick;
                GridRenderVolume::trilinear(accessor, p, &fromTree);
                brick.trilinear(p, &fromBrick);
                ASSERT_TRUE(sameBits(fromTree, fromBrick)) << p << ": " << fromTree << " against " << fromBrick;
                ++samples;
            }
        }
    }
    EXPECT_GT(samples, 10000);
}

/// Colours that differ voxel to voxel on a diagonal, over a coloured background.
openvdb::Vec3SGrid::Ptr colourDiagonal() {
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.1f, 0.2f, 0.3f));
    auto writer = grid->getAccessor();
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j)
            writer.setValue(Coord(i, j, i - j), openvdb::Vec3s(float(i), float(j), 0.5f * float(i + j)));
    }
    return grid;
}

TEST(VoxelBrick, SamplesColoursAsTheTreeToTheBit) {
    const auto grid = colourDiagonal();
    VoxelBrick<openvdb::Vec3SGrid> brick;
    brick.fill(*grid, CoordBBox(Coord(-1, -1, -11), Coord(11, 11, 11)));
    expectSamplesAsTheTree(*grid, brick, {-0.5, -0.5, -10.5}, {10.0, 10.0, 10.0}, {0.7, 0.9, 1.1});
}

/// Samples from @a first, @a step apart, along one grid axis.
template <typename GridT>
typename VoxelBrick<GridT>::Steps stepsFrom(double first, double step, int count) {
    typename VoxelBrick<GridT>::Steps steps;
    steps.count = count;
    for (int n = 0; n < count; ++n) {
        const double x = first + n * step;
        steps.base[n] = int(std::floor(x));
        steps.t[n] = x - steps.base[n];
    }
    return steps;
}

/// trilinearAlongAxes against trilinearAt at every sample of @a x by @a y by @a z.
template <typename GridT>
void expectAlongAxesAsEachSample(const VoxelBrick<GridT>& brick, const typename VoxelBrick<GridT>::Steps& x,
                                 const typename VoxelBrick<GridT>::Steps& y,
                                 const typename VoxelBrick<GridT>::Steps& z) {
    constexpr int channels = std::is_same_v<typename GridT::ValueType, openvdb::Vec3s> ? 3 : 1;
    float blended[kBlockDim][kBlockDim][kBlockDim][channels];
    brick.trilinearAlongAxes(x, y, z, [&](int a, int b, int c) { return blended[a][b][c]; });
    for (int a = 0; a < x.count; ++a) {
        for (int b = 0; b < y.count; ++b) {
            for (int c = 0; c < z.count; ++c) {
                float each[channels];
                brick.trilinearAt(Coord(x.base[a], y.base[b], z.base[c]), openvdb::Vec3d(x.t[a], y.t[b], z.t[c]), each);
                for (int ch = 0; ch < channels; ++ch) {
                    ASSERT_TRUE(sameBits(each[ch], blended[a][b][c][ch])) << a << " " << b << " " << c;
                }
            }
        }
    }
}

// The float range's ends and its denormals: the blend is the tree's, in doubles, so
// neither overflows nor flushes where the tree's does not.
TEST(VoxelBrick, SamplesTheFloatRangesEndsAndDenormalsAsTheTree) {
    openvdb::FloatGrid grid(0.0f);
    auto writer = grid.getAccessor();
    const float values[] = {3.0e38f, -3.0e38f, 1e-45f, -1e-45f, FLT_MAX, 1e-38f};
    for (int i = 0; i < 12; ++i) {
        for (int j = 0; j < 3; ++j) writer.setValue(Coord(i, j, i % 4), values[(i + j) % 6]);
    }
    VoxelBrick<openvdb::FloatGrid> brick;
    brick.fill(grid, CoordBBox(Coord(-1, -1, -1), Coord(13, 4, 5)));
    expectSamplesAsTheTree(grid, brick, {-0.5, -0.5, -0.5}, {12.0, 3.0, 4.0}, {0.25, 0.5, 0.5});
    // Blended axis by axis, too: lerp by lerp the same doubles.
    expectAlongAxesAsEachSample(brick, stepsFrom<openvdb::FloatGrid>(-0.5, 1.7, 8),
                                stepsFrom<openvdb::FloatGrid>(2.9, -0.4, 8),
                                stepsFrom<openvdb::FloatGrid>(-0.3, 0.6, 8));
}

// A block whose samples run along the grid's axes blends its brick axis by axis,
// sharing lerps between samples: finer and coarser than the voxels, running
// backwards, and with fewer than eight samples a side, it must give each sample's
// own trilinear blend, bit for bit.
TEST(VoxelBrick, BlendsAlongTheAxesAsSampleBySample) {
    const auto grid = patchwork();
    VoxelBrick<openvdb::FloatGrid> brick;
    brick.fill(*grid, CoordBBox(Coord(-14, -13, -12), Coord(36, 13, 14)));
    using Steps = VoxelBrick<openvdb::FloatGrid>::Steps;
    const Steps finer = stepsFrom<openvdb::FloatGrid>(-3.3, 0.6, 8);
    const Steps coarser = stepsFrom<openvdb::FloatGrid>(10.2, 2.1, 8);
    const Steps backwards = stepsFrom<openvdb::FloatGrid>(5.7, -1.3, 8);
    const Steps few = stepsFrom<openvdb::FloatGrid>(-11.5, 0.7, 3);
    expectAlongAxesAsEachSample(brick, finer, backwards, coarser);
    expectAlongAxesAsEachSample(brick, coarser, few, backwards);
    expectAlongAxesAsEachSample(brick, backwards, finer, few);

    VoxelBrick<openvdb::Vec3SGrid> colourBrick;
    colourBrick.fill(*colourDiagonal(), CoordBBox(Coord(-1, -1, -11), Coord(11, 11, 11)));
    expectAlongAxesAsEachSample(colourBrick, stepsFrom<openvdb::Vec3SGrid>(0.2, 1.1, 8),
                                stepsFrom<openvdb::Vec3SGrid>(9.4, -0.9, 7),
                                stepsFrom<openvdb::Vec3SGrid>(-9.9, 2.3, 8));
}

}  // namespace
}  // namespace gvr
