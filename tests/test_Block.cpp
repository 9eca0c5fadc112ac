// Blocks: blockVoxel numbers a block's voxels as blockOffset does, as OpenVDB's
// leaf nodes number theirs.

#include "pipeline/Block.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace gvr
