#include "pipeline/BlockBins.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace gvr {

void BlockBins::findTruncatedBounds(const GaussianField& field) {
    const std::vector<ActiveGaussian>& gaussians = field.gaussians();
    mTruncated.resize(gaussians.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, gaussians.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              truncatedBounds(gaussians[i], field.cutoffSigmas(), mTruncated[i].lower.data(),
                                              mTruncated[i].upper.data());
                          }
                      });
}

void BlockBins::clear() {
    std::vector<std::vector<std::uint32_t>>().swap(mBins);
    std::vector<Box>().swap(mBinned);
    std::vector<Box>().swap(mTruncated);
}

void BlockBins::build(const GaussianField& field) {
    findTruncatedBounds(field);
    mBinned = field.bvh().boxes();
    mBins.resize(mGrid.blockCount());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, mBins.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
            std::vector<std::uint32_t> hits;
            for (std::size_t b = range.begin(); b != range.end(); ++b) {
                const openvdb::Coord o = mGrid.origin(std::uint32_t(b));
                const float lower[3] = {o.x() - 0.5f, o.y() - 0.5f, o.z() - 0.5f};
                const float upper[3] = {o.x() + kBlockDim - 0.5f, o.y() + kBlockDim - 0.5f, o.z() + kBlockDim - 0.5f};
                if (mBinned.empty()) {
                    hits.clear();
                } else {
                    field.bvh().overlapping(lower, upper, hits);
                }
                std::sort(hits.begin(), hits.end());
                // A fresh list of the exact size: reusing the old one would keep the
                // capacity of its largest size, which early, wide Gaussians set.
                mBins[b] = std::vector<std::uint32_t>(hits.begin(), hits.end());
            }
        });
}

std::size_t BlockBins::follow(const GaussianField& field) {
    findTruncatedBounds(field);
    std::size_t moved = 0;
    // In index order, so that the bins do not depend on the threads.
    for (std::uint32_t i = 0; i < mTruncated.size(); ++i) {
        const Box& tight = mTruncated[i];
        const Box& binned = mBinned[i];
        bool inside = true;
        for (int a = 0; a < 3; ++a)
            inside = inside && tight.lower[a] >= binned.lower[a] && tight.upper[a] <= binned.upper[a];
        if (inside) continue;
        ++moved;
        Box grown = tight;
        for (int a = 0; a < 3; ++a) {
            const float grow = mSlackVoxels + mSlackFraction * 0.5f * (grown.upper[a] - grown.lower[a]);
            grown.lower[a] -= grow;
            grown.upper[a] += grow;
        }
        addToBlocks(i, grown);
        mBinned[i] = grown;
    }
    return moved;
}

void BlockBins::addToBlocks(std::uint32_t gaussian, const Box& box) {
    int lo[3], hi[3];
    mGrid.blockRange(box.lower.data(), box.upper.data(), lo, hi);
    for (int bz = lo[2]; bz <= hi[2]; ++bz) {
        for (int by = lo[1]; by <= hi[1]; ++by) {
            for (int bx = lo[0]; bx <= hi[0]; ++bx) {
                std::vector<std::uint32_t>& bin = mBins[mGrid.blockAt(bx, by, bz)];
                const auto at = std::lower_bound(bin.begin(), bin.end(), gaussian);
                if (at != bin.end() && *at == gaussian) continue;
                const std::ptrdiff_t offset = at - bin.begin();
                // Grow by an eighth, not the doubling insert() would make: a list
                // gains few Gaussians between builds.
                if (bin.size() == bin.capacity()) bin.reserve(bin.size() + bin.size() / 8 + 4);
                bin.insert(bin.begin() + offset, gaussian);
            }
        }
    }
}

const std::vector<std::uint32_t>& BlockBins::gaussiansNear(const float x[3]) const {
    const openvdb::Coord nearest(int(std::floor(x[0] + 0.5f)), int(std::floor(x[1] + 0.5f)),
                                 int(std::floor(x[2] + 0.5f)));
    return mBins[mGrid.blockOf(
        openvdb::Coord::minComponent(openvdb::Coord::maxComponent(nearest, mGrid.box().min()), mGrid.box().max()))];
}

std::size_t BlockBins::pairCount() const {
    std::size_t pairs = 0;
    for (const auto& bin : mBins) pairs += bin.size();
    return pairs;
}

}  // namespace gvr
