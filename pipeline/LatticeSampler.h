/// @file LatticeSampler.h
/// @brief The Gaussian field at the voxel centres of any lattice, one 8^3 block at a
/// time: what export (onto grids) and the renderer (onto slice stacks) share.
#pragma once

#include "pipeline/Block.h"
#include "pipeline/GaussianField.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace gvr {

/// Where to sample: the voxel centres of @a box, placed in the world (mm) by
/// @a worldFromIndex (OpenVDB's row-vector convention).
struct Lattice {
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
    openvdb::CoordBBox box;
};

/// The source's own lattice: voxels (0, 0, 0) to dims - 1.
Lattice sourceLattice(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims);

/// The source's extent (its voxel cells, edge to edge) covered by voxels of
/// @a voxelSizeMm along each of the source's index axes, starting at its corner.
/// Axes keep their direction, so oblique and sheared volumes stay aligned.
/// @throw InputError when the voxel size is not positive, exceeds the source's
///        longest extent, or would need more than 2^31 voxels along an axis.
Lattice resizedLattice(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims, double voxelSizeMm);

/// The voxel size that puts @a samples voxels along the source's longest axis (in mm).
double voxelSizeForResolution(const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims, int samples);

/// Whether the centre of every voxel of @a voxels, placed by @a cellsFromVoxels,
/// lies inside @a cells.
bool allVoxelsInside(const openvdb::CoordBBox& voxels, const openvdb::math::Mat4d& cellsFromVoxels,
                     const openvdb::BBoxd& cells);

/// The Gaussians whose reach (a box of lattice voxels each) overlaps each block, in
/// ascending order: one pass over the boxes instead of a BVH query per block.
class BlockLists {
public:
    BlockLists(const std::vector<openvdb::CoordBBox>& reach, const BlockSlots& slots);
    const std::uint32_t* begin(std::size_t slot) const { return mGaussians.data() + mStarts[slot]; }
    const std::uint32_t* end(std::size_t slot) const { return mGaussians.data() + mStarts[slot + 1]; }
    std::size_t count(std::size_t slot) const { return mStarts[slot + 1] - mStarts[slot]; }

private:
    std::vector<std::size_t> mStarts;  ///< by slot, and one past the last
    std::vector<std::uint32_t> mGaussians;
};

/// How sampleBlock() evaluates each Gaussian over a block.
enum class BlockEvaluation {
    /// Point by point, as GaussianField::evaluate does: the very same floats.
    Exact,
    /// Along each row of the block as one quadratic, through an exp the compiler
    /// vectorises: several times faster. Each term is within 1e-6 of its exact
    /// value, relative to the Gaussian's peak, except where a sample lies within
    /// rounding of the truncation edge and one of the two keeps a term the other cuts.
    /// Eight samples at a time where the processor has AVX2, else four.
    Rows,
    /// As rows, but four samples at a time on any processor: what rows computes
    /// without AVX2, so that tests can check the two agree.
    RowsFourLanes,
};

/// Evaluates @a field, which lives in the index space that @a fieldWorldFromIndex
/// places in the world, at the voxel centres of a lattice. Each block takes the
/// Gaussians whose truncated bounds reach it from lists made once (BlockLists), then
/// adds them up in index order, the order GaussianField::evaluate sums in. Build
/// once, then sample blocks from many threads.
class LatticeSampler {
public:
    /// @param fieldBox  the voxels the field stands for (its source volume): lattice
    ///                  points outside their cells get nothing, as outside the volume
    LatticeSampler(const GaussianField& field, const openvdb::math::Mat4d& fieldWorldFromIndex, const Lattice& lattice,
                   const openvdb::CoordBBox& fieldBox);

    /// Origins of the blocks that at least one Gaussian reaches, in z, y, x order.
    std::vector<openvdb::Coord> occupiedBlocks() const;

    /// Adds the field (normalised units, channels() floats per voxel) into @a sums at
    /// blockOffset() of each voxel of the block at @a origin that lies in the
    /// lattice; voxels no Gaussian reaches are left as they were.
    /// When the Gaussians reaching the block could add up to at most @a skipUpTo
    /// (the sum of their peak |amplitude|, normalised units) anywhere in it, nothing
    /// is added and the block counts as empty: a caller that cannot see such values
    /// (a transfer function transparent there) skips the work.
    /// @return the block's voxels inside the lattice (empty if none, or skipped).
    openvdb::CoordBBox sampleBlock(const openvdb::Coord& origin, float* sums, float skipUpTo = -1.0f,
                                   BlockEvaluation evaluation = BlockEvaluation::Exact) const;

    int channels() const { return mField.channels(); }
    const Lattice& lattice() const { return mLattice; }
    /// How many Gaussians reach the lattice at all.
    std::size_t reachingGaussians() const;

private:
    /// The most the Gaussians @a hits can add up to at any point of the field-space
    /// box [lower, upper], in any channel.
    float reachCeiling(const std::uint32_t* hits, const std::uint32_t* hitsEnd, const float lower[3],
                       const float upper[3], int channels) const;
    /// Adds Gaussian @a index over @a reached, row by row (BlockEvaluation::Rows).
    void addRows(std::uint32_t index, const openvdb::Coord& origin, const openvdb::CoordBBox& reached,
                 const std::int32_t inCells[], float* sums, bool eightLanes) const;

    const GaussianField& mField;
    Lattice mLattice;
    openvdb::math::Mat4d mFieldFromLattice;
    openvdb::Vec3d mLatticeSteps[3];         ///< field-space step along each lattice axis
    openvdb::BBoxd mFieldCells;              ///< fieldBox grown by half a voxel: its cells, edge to edge
    std::vector<openvdb::CoordBBox> mReach;  ///< lattice voxels each Gaussian can reach
    BlockSlots mSlots;
    BlockLists mLists;
};

}  // namespace gvr
