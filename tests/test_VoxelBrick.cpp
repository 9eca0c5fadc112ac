// A brick must sample exactly as the tree does: a stack built from bricks is the
// stack built before them, bit for bit.
#include "render/VoxelBrick.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>

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
            for (int k = -12; k < 12; ++k) accessor.setValue(Coord(i, j, k), float((i * 31 + j * 17 + k * 7) % 23) * 0.37f);
        }
    }
    grid->tree().fill(CoordBBox(Coord(16, -8, -8), Coord(31, 7, 7)), 40.0f);  // whole leaves: tiles
    return grid;
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

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

TEST(VoxelBrick, SamplesColoursAsTheTreeToTheBit) {
    openvdb::Vec3SGrid grid(openvdb::Vec3s(0.1f, 0.2f, 0.3f));
    auto writer = grid.getAccessor();
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j) writer.setValue(Coord(i, j, i - j), openvdb::Vec3s(float(i), float(j), 0.5f * float(i + j)));
    }
    const auto accessor = grid.getConstAccessor();
    VoxelBrick<openvdb::Vec3SGrid> brick;
    brick.fill(grid, CoordBBox(Coord(-1, -1, -11), Coord(11, 11, 11)));
    for (double x = -0.5; x < 10.0; x += 0.7) {
        for (double y = -0.5; y < 10.0; y += 0.9) {
            for (double z = -10.5; z < 10.0; z += 1.1) {
                float fromTree[3], fromBrick[3];
                GridRenderVolume::trilinear(accessor, openvdb::Vec3d(x, y, z), fromTree);
                brick.trilinear(openvdb::Vec3d(x, y, z), fromBrick);
                for (int c = 0; c < 3; ++c) ASSERT_TRUE(sameBits(fromTree[c], fromBrick[c])) << x << " " << y << " " << z;
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
    const auto accessor = grid.getConstAccessor();
    VoxelBrick<openvdb::FloatGrid> brick;
    brick.fill(grid, CoordBBox(Coord(-1, -1, -1), Coord(13, 4, 5)));
    for (double x = -0.5; x < 12.0; x += 0.25) {
        for (double y = -0.5; y < 3.0; y += 0.5) {
            for (double z = -0.5; z < 4.0; z += 0.5) {
                float fromTree, fromBrick;
                GridRenderVolume::trilinear(accessor, openvdb::Vec3d(x, y, z), &fromTree);
                brick.trilinear(openvdb::Vec3d(x, y, z), &fromBrick);
                ASSERT_TRUE(std::isfinite(fromBrick)) << x << " " << y << " " << z;
                ASSERT_TRUE(sameBits(fromTree, fromBrick)) << x << " " << y << " " << z;
            }
        }
    }
}

}  // namespace
}  // namespace gvr
