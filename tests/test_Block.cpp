// Blocks: blockVoxel numbers a block's voxels as blockOffset does, as OpenVDB's
// leaf nodes number theirs; BlockSlots numbers the blocks over a box as
// blockOrigins lists them, and visits those a box overlaps.

#include "pipeline/Block.h"

#include <gtest/gtest.h>

#include <vector>

namespace gvr {
namespace {

TEST(Block, BlockVoxelAndBlockOffsetAreInverseAndFollowOpenVdbsLeafOrder) {
    const openvdb::Coord origin(-16, 8, 24);
    openvdb::FloatTree::LeafNodeType leaf(origin);
    for (int offset = 0; offset < kBlockVoxels; ++offset) {
        const openvdb::Coord voxel = blockVoxel(origin, offset);
        EXPECT_EQ(blockOffset(voxel), offset);
        EXPECT_EQ(leaf.offsetToGlobalCoord(openvdb::Index(offset)), voxel);
    }
}

TEST(BlockSlots, NumberBlocksAsBlockOriginsListsThemAlsoAtNegativeUnalignedCorners) {
    const openvdb::CoordBBox box(openvdb::Coord(-13, 5, -1), openvdb::Coord(20, 9, 17));
    const BlockSlots slots(box);
    const std::vector<openvdb::Coord> origins = blockOrigins(box);
    ASSERT_EQ(slots.size(), origins.size());
    for (std::size_t slot = 0; slot < origins.size(); ++slot) {
        EXPECT_EQ(slots.originOf(slot), origins[slot]);
        EXPECT_EQ(slots.slotOf(slots.blockOf(origins[slot] + openvdb::Coord(7))), slot);
    }
    EXPECT_EQ(slots.slotOf(slots.blockOf(box.min())), 0u);
    EXPECT_EQ(slots.slotOf(slots.blockOf(box.max())), origins.size() - 1);
}

TEST(BlockSlots, VisitTheSlotsOfExactlyTheBlocksABoxOverlapsInSlotOrder) {
    const openvdb::CoordBBox box(openvdb::Coord(-13, 5, -1), openvdb::Coord(20, 9, 17));
    const BlockSlots slots(box);
    const openvdb::CoordBBox part(openvdb::Coord(-9, 6, 7), openvdb::Coord(8, 9, 8));
    std::vector<std::size_t> visited, expected;
    slots.forEachSlotOver(part, [&](std::size_t slot) { visited.push_back(slot); });
    for (std::size_t slot = 0; slot < slots.size(); ++slot) {
        const openvdb::Coord o = slots.originOf(slot);
        if (part.hasOverlap(openvdb::CoordBBox(o, o.offsetBy(kBlockDim - 1)))) expected.push_back(slot);
    }
    EXPECT_EQ(visited, expected);
    EXPECT_EQ(expected.size(), 4u * 2u * 2u);  // x from block -16 to 8, y and z from 0 to 8
}

}  // namespace
}  // namespace gvr
