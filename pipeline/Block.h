/// @file Block.h
/// @brief The 8^3 blocks that the fit, the sampler and the targets work in: their
/// size, and the one voxel order inside them.
#pragma once

#include <openvdb/openvdb.h>

namespace gvr {

/// Blocks are 8^3 voxels, aligned like OpenVDB leaf nodes, with the same voxel order.
constexpr int kBlockDim = 8;
constexpr int kBlockVoxels = kBlockDim * kBlockDim * kBlockDim;

/// Offset of @a ijk inside its block: z fastest, as openvdb::tree::LeafNode numbers voxels.
inline int blockOffset(const openvdb::Coord& ijk) {
    return ((ijk.x() & (kBlockDim - 1)) * kBlockDim + (ijk.y() & (kBlockDim - 1))) * kBlockDim + (ijk.z() & (kBlockDim - 1));
}

/// The voxel at @a offset (blockOffset's numbering) of the block at @a origin.
inline openvdb::Coord blockVoxel(const openvdb::Coord& origin, int offset) {
    return origin.offsetBy(offset / (kBlockDim * kBlockDim), (offset / kBlockDim) % kBlockDim, offset % kBlockDim);
}

}  // namespace gvr
