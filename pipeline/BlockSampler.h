/// @file BlockSampler.h
/// @brief Which 8^3 blocks a step of the voxel loss evaluates: the paper's importance
/// sampling, drawn a block at a time and still unbiased.
///
/// The paper draws voxels from p(x) = lambda/n + (1 - lambda) p_imp(x), p_imp
/// proportional to recent error + epsilon. Here p_imp is constant over a block (its
/// recent mean squared error), so block b carries the mass P_b = sum of p over its
/// trainable voxels. A draw takes each block independently with probability
/// pi_b = min(1, B P_b) (Poisson sampling, about B blocks): the blocks with the
/// highest error are always in. Inside a block it evaluates one sub-lattice of the
/// 64 rows along z, those with (x + y) mod k = phase for a random phase, so a voxel
/// is evaluated with probability pi_b / k; weighting it by k / pi_b makes the
/// weighted sum of squared residuals an unbiased estimate of the dense sum.
#pragma once

#include "pipeline/BlockGrid.h"

#include <cstdint>
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

struct SampledBlock {
    std::uint32_t block;
    std::uint32_t rowPhase;  ///< rows with (x + y) mod rowStride = rowPhase
    float weight;            ///< rowStride / pi_b
};

class BlockSampler {
public:
    /// Starts with the same error everywhere. @a rowStride k >= 1: every k-th row.
    BlockSampler(const BlockGrid& grid, const ImportanceSettings& settings, int rowStride);

    /// About @a voxels voxel samples (voxels * k / 512 blocks expected), in block
    /// order; the same seed gives the same blocks.
    std::vector<SampledBlock> draw(double voxels, std::uint64_t seed) const;
    /// pi_b for a draw of @a voxels voxel samples.
    double inclusionProbability(std::uint32_t block, double voxels) const;

    /// Folds each drawn block's mean squared residual (over the voxels evaluated)
    /// into its recent error.
    void recordErrors(const std::vector<SampledBlock>& blocks, const std::vector<double>& meanSquared);
    void setBlockError(std::uint32_t block, double error);
    int rowStride() const { return mRowStride; }

private:
    void rebuildTotal();

    const BlockGrid& mGrid;
    ImportanceSettings mSettings;
    int mRowStride;
    std::vector<double> mError;  ///< by block
    double mTotal = 0.0;         ///< sum over blocks of (error + epsilon) * trainable voxels
};

/// The smallest y >= @a yFrom whose row (x, y) of a block is in the sub-lattice of
/// @a phase, (x + y) mod rowStride = phase; the next ones follow every @a rowStride.
inline int firstSampledY(int x, int yFrom, int rowStride, std::uint32_t phase) {
    const int shift = (int(phase) - x - yFrom) % rowStride;
    return yFrom + (shift < 0 ? shift + rowStride : shift);
}

}  // namespace gvr
