#include "ImportanceSampler.h"

#include <algorithm>
#include <random>
#include <stdexcept>

namespace gvr {

namespace {
constexpr int kBlock = 8;
}

ImportanceSampler::ImportanceSampler(const openvdb::CoordBBox& box, const ImportanceSettings& settings)
    : mBox(box), mSettings(settings) {
    const openvdb::Coord extent = box.dim();
    mBlocks = openvdb::Coord((extent.x() + kBlock - 1) / kBlock, (extent.y() + kBlock - 1) / kBlock,
                             (extent.z() + kBlock - 1) / kBlock);
    const std::size_t count = std::size_t(mBlocks.x()) * mBlocks.y() * mBlocks.z();
    mBlockVoxels.resize(count);
    for (std::uint32_t b = 0; b < count; ++b) {
        const openvdb::Coord lower = blockOrigin(b);
        const openvdb::Coord upper = openvdb::Coord::minComponent(lower.offsetBy(kBlock - 1), box.max());
        mBlockVoxels[b] = std::uint32_t(openvdb::CoordBBox(lower, upper).volume());
    }
    mBlockError.assign(count, 1.0);
    rebuildDistribution();
}

openvdb::Coord ImportanceSampler::blockOrigin(std::uint32_t block) const {
    const int bx = int(block % std::uint32_t(mBlocks.x()));
    const int by = int((block / std::uint32_t(mBlocks.x())) % std::uint32_t(mBlocks.y()));
    const int bz = int(block / (std::uint32_t(mBlocks.x()) * std::uint32_t(mBlocks.y())));
    return mBox.min().offsetBy(bx * kBlock, by * kBlock, bz * kBlock);
}

std::uint32_t ImportanceSampler::blockOf(const openvdb::Coord& ijk) const {
    const openvdb::Coord local = ijk - mBox.min();
    return std::uint32_t(((local.z() / kBlock) * mBlocks.y() + local.y() / kBlock) * mBlocks.x() +
                         local.x() / kBlock);
}

void ImportanceSampler::rebuildDistribution() {
    mCumulative.resize(mBlockError.size());
    double total = 0.0;
    for (std::size_t b = 0; b < mBlockError.size(); ++b) {
        total += (mBlockError[b] + mSettings.epsilon) * mBlockVoxels[b];
        mCumulative[b] = total;
    }
    mExcludedMass = 0.0;
    const openvdb::Coord extent = mBox.dim();
    for (std::uint64_t key : mExcluded) {
        const std::uint64_t x = key % std::uint64_t(extent.x()), rest = key / std::uint64_t(extent.x());
        const openvdb::Coord local(int(x), int(rest % std::uint64_t(extent.y())), int(rest / std::uint64_t(extent.y())));
        mExcludedMass += probability(mBox.min() + local);
    }
}

double ImportanceSampler::probability(const openvdb::Coord& ijk) const {
    const double n = double(mBox.volume());
    const std::uint32_t block = blockOf(ijk);
    const double importance = (mBlockError[block] + mSettings.epsilon) / mCumulative.back();
    return mSettings.uniformShare / n + (1.0 - mSettings.uniformShare) * importance;
}

openvdb::Coord ImportanceSampler::drawOne(std::mt19937_64& random) const {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    openvdb::Coord origin = mBox.min(), upper = mBox.max();
    if (unit(random) >= mSettings.uniformShare) {
        const double target = unit(random) * mCumulative.back();
        const std::size_t block = std::min<std::size_t>(
            std::upper_bound(mCumulative.begin(), mCumulative.end(), target) - mCumulative.begin(),
            mCumulative.size() - 1);
        origin = blockOrigin(std::uint32_t(block));
        upper = openvdb::Coord::minComponent(origin.offsetBy(kBlock - 1), mBox.max());
    }
    openvdb::Coord ijk;
    for (int axis = 0; axis < 3; ++axis) {
        const int span = upper[axis] - origin[axis] + 1;
        ijk[axis] = origin[axis] + std::min(int(unit(random) * span), span - 1);
    }
    return ijk;
}

std::vector<VoxelSample> ImportanceSampler::draw(std::size_t count, std::uint64_t seed) const {
    std::mt19937_64 random(seed);
    const double remaining = double(mBox.volume()) - double(mExcluded.size());
    std::vector<VoxelSample> samples(count);
    for (VoxelSample& sample : samples) {
        openvdb::Coord ijk = drawOne(random);
        while (isExcluded(ijk)) ijk = drawOne(random);  // at most half the box: ends quickly
        sample.ijk = ijk;
        sample.block = blockOf(ijk);
        sample.weight = float((1.0 - mExcludedMass) / (remaining * probability(ijk)));
    }
    return samples;
}

std::uint64_t ImportanceSampler::packed(const openvdb::Coord& ijk) const {
    const openvdb::Coord local = ijk - mBox.min();
    const openvdb::Coord extent = mBox.dim();
    return (std::uint64_t(local.z()) * std::uint64_t(extent.y()) + std::uint64_t(local.y())) *
               std::uint64_t(extent.x()) + std::uint64_t(local.x());
}

bool ImportanceSampler::isExcluded(const openvdb::Coord& ijk) const {
    return !mExcluded.empty() && mExcluded.count(packed(ijk)) > 0;
}

void ImportanceSampler::exclude(const std::vector<openvdb::Coord>& voxels) {
    for (const openvdb::Coord& ijk : voxels) {
        if (!mBox.isInside(ijk)) throw std::invalid_argument("excluded voxel outside the sampled box");
        mExcluded.insert(packed(ijk));
    }
    if (double(mExcluded.size()) > 0.5 * double(mBox.volume())) {
        throw std::invalid_argument("at most half the voxels may be excluded from sampling");
    }
    rebuildDistribution();
}

void ImportanceSampler::recordErrors(const std::vector<VoxelSample>& samples,
                                     const std::vector<float>& squaredResiduals) {
    std::vector<double> sum(mBlockError.size(), 0.0);
    std::vector<std::uint32_t> seen(mBlockError.size(), 0);
    for (std::size_t s = 0; s < samples.size(); ++s) {
        sum[samples[s].block] += squaredResiduals[s];
        ++seen[samples[s].block];
    }
    const double update = mSettings.errorUpdate;
    for (std::size_t b = 0; b < mBlockError.size(); ++b) {
        if (seen[b] > 0) mBlockError[b] = (1.0 - update) * mBlockError[b] + update * sum[b] / seen[b];
    }
    rebuildDistribution();
}

void ImportanceSampler::setBlockError(std::uint32_t block, double error) {
    mBlockError[block] = error;
    rebuildDistribution();
}

}  // namespace gvr
