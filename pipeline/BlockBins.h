/// @file BlockBins.h
/// @brief Which Gaussians may reach each 8^3 block: the fit's neighbour lists.
///
/// build() asks the field's Embree BVH once per block for the boxes that overlap
/// the block's voxel cells, as export does. Between builds, follow() keeps every
/// list a superset of the Gaussians that reach its block: a Gaussian whose truncated
/// bounds have left the box it was binned with is added to the blocks of its new
/// box, and nothing else is touched, so one moving Gaussian never re-bins the rest.
#pragma once

#include "pipeline/BlockGrid.h"
#include "pipeline/GaussianField.h"

#include <cstdint>
#include <vector>

namespace gvr {

/// How far a Gaussian's truncated bounds are grown where it is binned (voxels,
/// and a share of its half-extent), so that it may move a while in its blocks: the
/// fit's choice, which the benchmark of its kernel shares.
constexpr float kBinSlackVoxels = 0.5f;
constexpr float kBinSlackFraction = 0.05f;

class BlockBins {
public:
    /// @param slackVoxels, slackFraction  how far follow() grows a moved Gaussian's
    ///        truncated bounds (voxels, plus a share of its half-extent), so that it
    ///        may move on for a while before it needs new blocks
    BlockBins(const BlockGrid& grid, float slackVoxels, float slackFraction)
        : mGrid(grid), mSlackVoxels(slackVoxels), mSlackFraction(slackFraction) {}

    /// Bins every Gaussian of @a field by the boxes of its BVH, which must be current
    /// (GaussianField::rebuild with the same slack).
    void build(const GaussianField& field);
    /// After the field's Gaussians were re-activated (GaussianField::reactivate):
    /// bins each Gaussian that left its box again, adding
    /// it to the blocks of its grown bounds. @return how many had left.
    std::size_t follow(const GaussianField& field);

    /// Frees every bin, for a caller done with them until the next build().
    void clear();

    const BlockGrid& grid() const { return mGrid; }
    /// The Gaussians that may reach @a block, in ascending order.
    const std::vector<std::uint32_t>& gaussians(std::uint32_t block) const { return mBins[block]; }
    /// The Gaussians that may reach index-space point @a x, in ascending order: those
    /// of the block of its nearest voxel, which must lie in the grid's box.
    const std::vector<std::uint32_t>& gaussiansNear(const float x[3]) const;
    /// Sum over blocks of the Gaussians binned there.
    std::size_t pairCount() const;
    /// Gaussian @a index's truncated bounds (no slack), as of the last build() or follow().
    const Box& truncated(std::uint32_t index) const { return mTruncated[index]; }

private:
    void findTruncatedBounds(const GaussianField& field);
    void addToBlocks(std::uint32_t gaussian, const Box& box);

    const BlockGrid& mGrid;
    float mSlackVoxels, mSlackFraction;
    std::vector<std::vector<std::uint32_t>> mBins;  ///< by block
    std::vector<Box> mBinned;                       ///< by Gaussian: the box it is binned with
    std::vector<Box> mTruncated;                    ///< by Gaussian: its truncated bounds
};

}  // namespace gvr
