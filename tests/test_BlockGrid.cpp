// The box of voxels seen as 8^3 blocks: numbering, the blocks a box overlaps, and
// which voxels may be trained on (inside the box, not set aside).

#include "pipeline/BlockGrid.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;

TEST(BlockGrid, BlocksAreAlignedLikeLeavesAndNumberedXFastest) {
    const BlockGrid grid(CoordBBox(Coord(-3, 0, 9), Coord(20, 7, 16)));  // negative, and not multiples of 8
    ASSERT_EQ(grid.blockCount(), 4u * 1u * 2u);
    EXPECT_EQ(grid.origin(0), Coord(-8, 0, 8));
    EXPECT_EQ(grid.origin(1), Coord(0, 0, 8));
    EXPECT_EQ(grid.origin(4), Coord(-8, 0, 16));
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) {
        EXPECT_EQ(grid.blockOf(grid.origin(b).offsetBy(7)), b) << "the far corner of block " << b;
    }
    EXPECT_EQ(grid.blockAt(1, 0, 1), 5u);
}

TEST(BlockGrid, TrainableVoxelsAreTheBoxsVoxelsLessTheExcluded) {
    const CoordBBox box(Coord(-3, 0, 9), Coord(20, 7, 16));
    const std::vector<Coord> excluded = {Coord(0, 0, 9), Coord(20, 7, 16), Coord(0, 0, 9)};
    const BlockGrid grid(box, excluded);
    EXPECT_EQ(grid.trainableVoxels(), box.volume() - 2) << "a repeat changes nothing";
    EXPECT_THROW(BlockGrid(box, {Coord(100, 0, 0)}), std::invalid_argument);
    EXPECT_FALSE(grid.trainable(Coord(0, 0, 9)));
    EXPECT_FALSE(grid.trainable(Coord(20, 7, 16)));
    EXPECT_FALSE(grid.trainable(Coord(21, 0, 9))) << "outside the box";
    EXPECT_TRUE(grid.trainable(Coord(1, 0, 9)));
    EXPECT_TRUE(grid.trainable(Coord(-3, 0, 9)));
    std::uint64_t sum = 0;
    std::int32_t mask[kBlockVoxels];
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) {
        grid.trainableMask(b, mask);
        std::uint32_t set = 0;
        for (int k = 0; k < kBlockVoxels; ++k) set += mask[k] != 0;
        EXPECT_EQ(set, grid.trainableVoxels(b)) << "block " << b;
        sum += set;
    }
    EXPECT_EQ(sum, grid.trainableVoxels());
    grid.trainableMask(grid.blockOf(Coord(0, 0, 9)), mask);
    EXPECT_EQ(mask[blockOffset(Coord(0, 0, 9))], 0);
    EXPECT_EQ(mask[blockOffset(Coord(1, 0, 9))], -1);
    grid.trainableMask(grid.blockOf(Coord(-3, 0, 9)), mask);
    EXPECT_EQ(mask[blockOffset(Coord(-4, 0, 9))], 0) << "outside the box";
}

TEST(BlockGrid, BlockRangeCoversTheVoxelCellsABoxOverlaps) {
    const BlockGrid grid(CoordBBox(Coord(0), Coord(31)));
    int lo[3], hi[3];
    const float lower[3] = {7.4f, 0.0f, 15.6f}, upper[3] = {7.6f, 0.0f, 16.2f};
    grid.blockRange(lower, upper, lo, hi);
    EXPECT_EQ(lo[0], 0);  // voxel 7's cell reaches 7.5
    EXPECT_EQ(hi[0], 1);  // voxel 8's cell starts at 7.5
    EXPECT_EQ(lo[1], 0);
    EXPECT_EQ(hi[1], 0);
    EXPECT_EQ(lo[2], 2);  // 15.6 is in voxel 16's cell
    EXPECT_EQ(hi[2], 2);
    const float farLower[3] = {100, 100, 100}, farUpper[3] = {101, 101, 101};
    grid.blockRange(farLower, farUpper, lo, hi);
    EXPECT_TRUE(lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) << "a box beyond the grid overlaps no block";
}

}  // namespace
}  // namespace gvr
