#include "pipeline/BlockGrid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gvr {

BlockGrid::BlockGrid(const openvdb::CoordBBox& box, const std::vector<openvdb::Coord>& excluded)
    : mBox(box), mSlots(box) {
    if (box.empty()) return;
    mTrainable.resize(mSlots.size());
    for (std::uint32_t b = 0; b < mTrainable.size(); ++b) {
        openvdb::CoordBBox voxels(origin(b), origin(b).offsetBy(kBlockDim - 1));
        voxels.intersect(box);
        mTrainable[b] = std::uint32_t(voxels.volume());
        mTotalTrainable += mTrainable[b];
    }
    exclude(excluded);
}

void BlockGrid::blockRange(const float lower[3], const float upper[3], int lo[3], int hi[3]) const {
    for (int a = 0; a < 3; ++a) {
        // Block k covers cells [first + 8k - 1/2, first + 8k + 7.5].
        const int first = mSlots.first()[a], count = mSlots.counts()[a];
        const double from = std::ceil((double(lower[a]) - first - (kBlockDim - 0.5)) / kBlockDim);
        const double to = std::floor((double(upper[a]) - first + 0.5) / kBlockDim);
        lo[a] = int(std::clamp(from, 0.0, double(count)));
        hi[a] = int(std::clamp(to, -1.0, double(count - 1)));
    }
}

void BlockGrid::exclude(const std::vector<openvdb::Coord>& voxels) {
    for (const openvdb::Coord& ijk : voxels) {
        if (!mBox.isInside(ijk)) throw std::invalid_argument("excluded voxel outside the box");
        const std::uint32_t block = blockOf(ijk);
        std::bitset<kBlockVoxels>& excluded = mExcluded[block];
        if (excluded.test(std::size_t(blockOffset(ijk)))) continue;
        excluded.set(std::size_t(blockOffset(ijk)));
        --mTrainable[block];
        --mTotalTrainable;
    }
}

bool BlockGrid::trainable(const openvdb::Coord& ijk) const {
    if (!mBox.isInside(ijk)) return false;
    const auto found = mExcluded.find(blockOf(ijk));
    return found == mExcluded.end() || !found->second.test(std::size_t(blockOffset(ijk)));
}

void BlockGrid::trainableMask(std::uint32_t block, std::int32_t mask[kBlockVoxels]) const {
    const openvdb::Coord o = origin(block);
    openvdb::CoordBBox voxels(o, o.offsetBy(kBlockDim - 1));
    if (mBox.isInside(voxels)) {
        std::fill(mask, mask + kBlockVoxels, -1);
    } else {
        std::fill(mask, mask + kBlockVoxels, 0);
        voxels.intersect(mBox);
        for (auto ijk = voxels.begin(); ijk; ++ijk) mask[blockOffset(*ijk)] = -1;
    }
    const auto found = mExcluded.find(block);
    if (found == mExcluded.end()) return;
    for (int offset = 0; offset < kBlockVoxels; ++offset) {
        if (found->second.test(std::size_t(offset))) mask[offset] = 0;
    }
}

}  // namespace gvr
