/// @file BlockGrid.h
/// @brief A box of voxels seen as 8^3 blocks aligned like OpenVDB leaves, with the
/// voxels that may be trained on: inside the box and not set aside.
///
/// The fit's block engine samples, bins and evaluates these blocks. A block may
/// stick out of the box (boxes need not be multiples of 8); its voxels outside are
/// never trained on, nor are the voxels set aside with exclude() (held-out voxels).
#pragma once

#include "pipeline/Block.h"

#include <openvdb/openvdb.h>

#include <bitset>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace gvr {

class BlockGrid {
public:
    BlockGrid() = default;
    /// @param excluded  voxels of @a box set aside: never trained on
    explicit BlockGrid(const openvdb::CoordBBox& box, const std::vector<openvdb::Coord>& excluded = {});

    const openvdb::CoordBBox& box() const { return mBox; }
    std::size_t blockCount() const { return mTrainable.size(); }
    /// Blocks are numbered as BlockSlots numbers them.
    openvdb::Coord origin(std::uint32_t block) const { return mSlots.originOf(block); }
    /// The block holding voxel @a ijk, which must lie in box().
    std::uint32_t blockOf(const openvdb::Coord& ijk) const { return std::uint32_t(mSlots.slotOf(mSlots.blockOf(ijk))); }
    /// The blocks whose voxel cells ([origin - 1/2, origin + 7.5] per axis) overlap the
    /// index-space box [lower, upper], as a range of block coordinates per axis; empty
    /// (some lo > hi) when none do.
    void blockRange(const float lower[3], const float upper[3], int lo[3], int hi[3]) const;
    std::uint32_t blockAt(int bx, int by, int bz) const { return std::uint32_t(mSlots.slotOf(bx, by, bz)); }

    /// Trainable voxels of a block, and of the whole box.
    std::uint32_t trainableVoxels(std::uint32_t block) const { return mTrainable[block]; }
    std::uint64_t trainableVoxels() const { return mTotalTrainable; }
    /// Whether voxel @a ijk lies in box() and was not set aside.
    bool trainable(const openvdb::Coord& ijk) const;
    /// -1 at the blockOffset() of each trainable voxel of @a block, 0 elsewhere.
    void trainableMask(std::uint32_t block, std::int32_t mask[kBlockVoxels]) const;

private:
    void exclude(const std::vector<openvdb::Coord>& voxels);

    openvdb::CoordBBox mBox;
    BlockSlots mSlots;
    std::vector<std::uint32_t> mTrainable;
    std::uint64_t mTotalTrainable = 0;
    std::unordered_map<std::uint32_t, std::bitset<kBlockVoxels>> mExcluded;  ///< by block, at blockOffset()
};

}  // namespace gvr
