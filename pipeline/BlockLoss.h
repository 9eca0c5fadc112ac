/// @file BlockLoss.h
/// @brief The voxel loss over sampled 8^3 blocks, with its gradient in the same pass.
///
/// Each block's Gaussians come from its bin. For each (Gaussian, block) pair the
/// Gaussian's q is a quadratic in the voxel position, stepped along the rows (z)
/// of the block and put through a polynomial exp several lanes at a time (pass 1,
/// which also keeps the kernel values). With the residuals known, pass 2 sums what
/// the pair's voxels give the gradient as moments in the block's frame (the sums of
/// t, t r and t r r^T, and of upstream * e), shifted once per pair to moments about
/// the Gaussian's mean (GradientSums): one gradient write per pair, not per voxel.
#pragma once

#include "pipeline/BlockBins.h"
#include "pipeline/BlockSampler.h"
#include "pipeline/Loss.h"
#include "pipeline/VolumeTarget.h"

#include <vector>

namespace gvr {

/// What one sampled block showed.
struct BlockOutcome {
    double squared = 0.0;      ///< sum of |f - t|^2 over the voxels evaluated (channels summed)
    std::uint32_t voxels = 0;  ///< trainable voxels evaluated
};

enum class BlockKernel {
    Best,       ///< eight lanes with fused multiply-adds where the processor has AVX2 and FMA, else four
    FourLanes,  ///< four lanes on any processor, for tests against best
};

struct BlockLossSettings {
    double scale = 1.0;  ///< multiplies every weighted squared residual
    int rowStride = 1;   ///< the sampler's k: rows with (x + y) mod k = the block's phase
    BlockKernel kernel = BlockKernel::Best;
};

/// L = scale * sum over @a blocks of weight_b * sum over the trainable voxels of the
/// block's sampled rows of |f(x) - t(x)|^2, f the truncated field at voxel centres.
/// The result does not depend on the thread count.
/// @param gradients  when not null, dL/dparams is added into its chunks, a fixed
///                   run of blocks per chunk
/// @param outcomes   when not null, receives one per block
double blockSquaredError(const GaussianField& field, const BlockBins& bins, const VolumeTarget& target,
                         const std::vector<SampledBlock>& blocks, const BlockLossSettings& settings,
                         GradientChunks* gradients = nullptr, std::vector<BlockOutcome>* outcomes = nullptr);

}  // namespace gvr
