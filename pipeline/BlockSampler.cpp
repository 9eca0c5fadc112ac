#include "pipeline/BlockSampler.h"

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {

/// SplitMix64's finaliser: a counter-based stream, so that each block's draw depends
/// on the seed and the block only, however the work is split.
std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

double unitFrom(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

}  // namespace

BlockSampler::BlockSampler(const BlockGrid& grid, const ImportanceSettings& settings, int rowStride)
    : mGrid(grid), mSettings(settings), mRowStride(std::max(rowStride, 1)), mError(grid.blockCount(), 1.0) {
    rebuildTotal();
}

void BlockSampler::rebuildTotal() {
    mTotal = 0.0;
    for (std::uint32_t b = 0; b < mError.size(); ++b)
        mTotal += (mError[b] + mSettings.epsilon) * mGrid.trainableVoxels(b);
}

double BlockSampler::inclusionProbability(std::uint32_t block, double voxels) const {
    const double trainable = mGrid.trainableVoxels(block);
    if (trainable == 0.0 || mTotal <= 0.0) return 0.0;
    const double lambda = mSettings.uniformShare;
    const double mass = lambda * trainable / double(mGrid.trainableVoxels()) +
                        (1.0 - lambda) * (mError[block] + mSettings.epsilon) * trainable / mTotal;
    const double blocks = voxels * mRowStride / double(kBlockVoxels);
    return std::min(1.0, blocks * mass);
}

std::vector<SampledBlock> BlockSampler::draw(double voxels, std::uint64_t seed) const {
    std::vector<SampledBlock> drawn;
    const std::uint64_t stream = mix(seed);
    for (std::uint32_t b = 0; b < mError.size(); ++b) {
        const double pi = inclusionProbability(b, voxels);
        if (pi <= 0.0) continue;
        const std::uint64_t bits = mix(stream ^ (std::uint64_t(b) * 0xd1b54a32d192ed03ull));
        if (unitFrom(bits) >= pi) continue;
        drawn.push_back({b, std::uint32_t(mix(bits) % std::uint64_t(mRowStride)), float(mRowStride / pi)});
    }
    return drawn;
}

void BlockSampler::recordErrors(const std::vector<SampledBlock>& blocks, const std::vector<double>& meanSquared) {
    const double update = mSettings.errorUpdate;
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        if (!std::isfinite(meanSquared[k])) continue;
        double& error = mError[blocks[k].block];
        error = (1.0 - update) * error + update * meanSquared[k];
    }
    rebuildTotal();
}

void BlockSampler::setBlockError(std::uint32_t block, double error) {
    mError[block] = error;
    rebuildTotal();
}

}  // namespace gvr
