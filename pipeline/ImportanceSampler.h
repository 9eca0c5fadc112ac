/// @file ImportanceSampler.h
/// @brief Draws voxels for the Monte Carlo voxel loss, in proportion to recent error.
///
/// Voxels come from p(x) = lambda/n + (1 - lambda) p_imp(x), where p_imp is
/// proportional to the recent mean squared error of x's 8^3 block plus epsilon.
/// Each sample carries the weight 1/(n p(x)) for exactly that p, so the weighted
/// mean of squared residuals is an unbiased estimate of the dense voxel MSE.
/// Voxels set aside with exclude() (the fit's held-out voxels) are never drawn; the
/// weights then estimate the MSE over the voxels that remain.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

namespace gvr {

struct ImportanceSettings {
    /// lambda: share of uniform sampling. 1 gives plain uniform sampling. Valid range [0, 1].
    double uniformShare = 0.3;
    /// epsilon added to every block's error (normalised units squared). Must be > 0
    /// so that every voxel keeps a chance to be drawn when lambda is 0.
    double epsilon = 1e-4;
    /// Weight of a block's newest error in its running average, in (0, 1].
    double errorUpdate = 0.5;
};

struct VoxelSample {
    openvdb::Coord ijk;
    float weight;         ///< 1 / (n p(ijk)), or over the remaining voxels after exclude()
    std::uint32_t block;  ///< the 8^3 block the voxel lies in
};

class ImportanceSampler {
public:
    /// Starts with the same error everywhere, i.e. uniform sampling.
    ImportanceSampler(const openvdb::CoordBBox& box, const ImportanceSettings& settings);

    /// Draws @a count voxels; the same seed gives the same samples.
    std::vector<VoxelSample> draw(std::size_t count, std::uint64_t seed) const;

    /// p(x), the probability of drawing voxel @a ijk in one draw before exclusion.
    double probability(const openvdb::Coord& ijk) const;

    /// Never draws these voxels. A draw then comes from p(x) / (1 - p(excluded)) over
    /// the n' remaining voxels, and its weight is (1 - p(excluded)) / (n' p(x)), so the
    /// weighted mean stays an unbiased estimate of the MSE over the remaining voxels.
    /// At most half the box may be excluded.
    void exclude(const std::vector<openvdb::Coord>& voxels);
    bool isExcluded(const openvdb::Coord& ijk) const;

    /// Folds squared residuals observed at @a samples into the blocks' errors.
    void recordErrors(const std::vector<VoxelSample>& samples, const std::vector<float>& squaredResiduals);

    /// Sets one block's error directly (tests, and warm starts).
    void setBlockError(std::uint32_t block, double error);
    std::uint32_t blockOf(const openvdb::Coord& ijk) const;
    std::size_t blockCount() const { return mBlockError.size(); }

private:
    void rebuildDistribution();
    openvdb::Coord blockOrigin(std::uint32_t block) const;
    openvdb::Coord drawOne(std::mt19937_64& random) const;
    std::uint64_t packed(const openvdb::Coord& ijk) const;

    openvdb::CoordBBox mBox;
    ImportanceSettings mSettings;
    openvdb::Coord mBlocks;                  // blocks along each axis
    std::vector<std::uint32_t> mBlockVoxels; // voxels inside the box per block
    std::vector<double> mBlockError;
    std::vector<double> mCumulative;         // running sum of (error + eps) * voxels
    std::unordered_set<std::uint64_t> mExcluded;
    double mExcludedMass = 0.0;              // p(excluded), summed over mExcluded
};

}  // namespace gvr
