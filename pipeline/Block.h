/// @file Block.h
/// @brief The 8^3 blocks that the fit, the sampler and the targets work in: their
/// size, the one voxel order inside them, and the one numbering of the blocks over a box.
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <vector>

namespace gvr {

/// Blocks are 8^3 voxels, aligned like OpenVDB leaf nodes, with the same voxel order.
constexpr int kBlockDim = 8;
constexpr int kBlockVoxels = kBlockDim * kBlockDim * kBlockDim;

/// Offset of @a ijk inside its block: z fastest, as openvdb::tree::LeafNode numbers voxels.
inline int blockOffset(const openvdb::Coord& ijk) {
    return ((ijk.x() & (kBlockDim - 1)) * kBlockDim + (ijk.y() & (kBlockDim - 1))) * kBlockDim +
           (ijk.z() & (kBlockDim - 1));
}

/// The voxel at @a offset (blockOffset's numbering) of the block at @a origin.
inline openvdb::Coord blockVoxel(const openvdb::Coord& origin, int offset) {
    return origin.offsetBy(offset / (kBlockDim * kBlockDim), (offset / kBlockDim) % kBlockDim, offset % kBlockDim);
}

/// The 8^3 blocks over a box of voxels, numbered in z, y, x order (x fastest) from
/// the block that holds the box's lowest corner: a block's number (slot) is where
/// the fit and the sampler keep what they know of it.
class BlockSlots {
public:
    BlockSlots() = default;
    explicit BlockSlots(const openvdb::CoordBBox& box) {
        if (box.empty()) return;
        mFirst = alignedDown(box.min());
        mCounts = blockOf(box.max()) + openvdb::Coord(1);
    }

    /// The block that holds @a voxel, counted in blocks from the first: inside the box.
    openvdb::Coord blockOf(const openvdb::Coord& voxel) const {
        const openvdb::Coord d = alignedDown(voxel) - mFirst;
        return {d.x() / kBlockDim, d.y() / kBlockDim, d.z() / kBlockDim};
    }
    std::size_t slotOf(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(mCounts.y()) + std::size_t(y)) * std::size_t(mCounts.x()) + std::size_t(x);
    }
    std::size_t slotOf(const openvdb::Coord& block) const { return slotOf(block.x(), block.y(), block.z()); }
    openvdb::Coord originOf(std::size_t slot) const {
        const std::size_t nx = std::size_t(mCounts.x()), ny = std::size_t(mCounts.y());
        return mFirst.offsetBy(int(slot % nx) * kBlockDim, int(slot / nx % ny) * kBlockDim,
                               int(slot / (nx * ny)) * kBlockDim);
    }
    /// Blocks along each axis.
    const openvdb::Coord& counts() const { return mCounts; }
    /// The first block's origin.
    const openvdb::Coord& first() const { return mFirst; }
    std::size_t size() const { return std::size_t(mCounts.x()) * std::size_t(mCounts.y()) * std::size_t(mCounts.z()); }

    /// Calls visit(slot) for each block that @a voxels (inside the box) overlaps, in slot order.
    template <typename Visit>
    void forEachSlotOver(const openvdb::CoordBBox& voxels, const Visit& visit) const {
        const openvdb::Coord low = blockOf(voxels.min()), high = blockOf(voxels.max());
        for (int z = low.z(); z <= high.z(); ++z) {
            for (int y = low.y(); y <= high.y(); ++y) {
                for (int x = low.x(); x <= high.x(); ++x) visit(slotOf(x, y, z));
            }
        }
    }

private:
    static openvdb::Coord alignedDown(const openvdb::Coord& ijk) {
        constexpr int kMask = ~(kBlockDim - 1);
        return {ijk.x() & kMask, ijk.y() & kMask, ijk.z() & kMask};
    }

    openvdb::Coord mFirst{0}, mCounts{0};
};

/// Origins of every block that overlaps @a box, in slot order.
inline std::vector<openvdb::Coord> blockOrigins(const openvdb::CoordBBox& box) {
    const BlockSlots slots(box);
    std::vector<openvdb::Coord> origins(slots.size());
    for (std::size_t slot = 0; slot < origins.size(); ++slot) origins[slot] = slots.originOf(slot);
    return origins;
}

}  // namespace gvr
