#include "pipeline/FieldAccuracy.h"

#include "pipeline/Fitter.h"
#include "pipeline/LatticeSampler.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <bitset>
#include <chrono>

namespace gvr {

namespace {

/// Adds the squared errors (channel mean) of the voxels of the block at @a origin
/// that lie in @a part into their slices (slices[0] is part.min().z()).
void measureBlock(const LatticeSampler& sampler, const VolumeTarget& target, const openvdb::Coord& origin,
                  const openvdb::CoordBBox& part, const VoxelMarking& marked, const ThresholdCut& cut,
                  std::vector<SliceSums>& slices) {
    const int channels = target.channels();
    float field[kBlockVoxels * 3] = {}, expected[kBlockVoxels * 3];
    sampler.sampleBlock(origin, field);
    target.blockValues(origin, expected);
    const std::bitset<kBlockVoxels> active = target.blockActive(origin);
    openvdb::CoordBBox voxels(origin, origin.offsetBy(kBlockDim - 1));
    voxels.intersect(part);
    for (auto ijk = voxels.beginZYX(); ijk; ++ijk) {
        const int offset = blockOffset(*ijk);
        float* value = field + offset * channels;
        cut.apply(value);
        double squared = 0.0;
        for (int c = 0; c < channels; ++c) {
            const double difference = double(value[c]) - double(expected[offset * channels + c]);
            squared += difference * difference;
        }
        squared /= channels;
        SliceSums& error = slices[std::size_t((*ijk).z() - part.min().z())];
        error.all += squared;
        if (active[offset]) {
            error.foreground += squared;
            ++error.foregroundVoxels;
        }
        if (marked && marked(*ijk)) {
            error.marked += squared;
            ++error.markedVoxels;
            if (active[offset]) {
                error.markedForeground += squared;
                ++error.markedForegroundVoxels;
            }
        }
    }
}

}  // namespace

std::vector<SliceSums> measureSliceSums(const GaussianField& field, const VolumeTarget& target, openvdb::CoordBBox part,
                                        const ProgressFn& progress, const VoxelMarking& marked,
                                        const ThresholdCut& cut) {
    part.intersect(target.box());
    std::vector<SliceSums> slices(part.empty() ? 0 : std::size_t(part.dim().z()));
    if (slices.empty()) return slices;
    // Export's own evaluation, block by block, so that the numbers are export's.
    const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(),
                                 Lattice{openvdb::math::Mat4d::identity(), part}, target.box());
    // One task per layer of blocks: each owns the slices it covers, so the sums do
    // not depend on the thread count.
    std::vector<std::vector<openvdb::Coord>> layers;
    for (const openvdb::Coord& origin : blockOrigins(part)) {
        if (layers.empty() || layers.back().front().z() != origin.z()) layers.emplace_back();
        layers.back().push_back(origin);
    }
    ProgressCounter counter(progress, layers.size());
    tbb::parallel_for(std::size_t(0), layers.size(), [&](std::size_t layer) {
        for (const openvdb::Coord& origin : layers[layer])
            measureBlock(sampler, target, origin, part, marked, cut, slices);
        counter.advance();
    });
    return slices;
}

double estimateMeasurementSeconds(const GaussianField& field, const VolumeTarget& target, std::size_t stride) {
    using Clock = std::chrono::steady_clock;
    const openvdb::CoordBBox box = target.box();
    if (box.empty() || stride == 0) return 0.0;
    const Clock::time_point start = Clock::now();
    const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(),
                                 Lattice{openvdb::math::Mat4d::identity(), box}, box);
    const double setUp = std::chrono::duration<double>(Clock::now() - start).count();
    const std::vector<openvdb::Coord> origins = blockOrigins(box);
    std::vector<openvdb::Coord> sample;
    for (std::size_t b = stride / 2; b < origins.size(); b += stride) sample.push_back(origins[b]);
    std::vector<SliceSums> slices(std::size_t(box.dim().z()));
    const Clock::time_point blocksStart = Clock::now();
    // One thread, as one of measureFieldAccuracy's workers spends it.
    for (const openvdb::Coord& origin : sample) measureBlock(sampler, target, origin, box, {}, {}, slices);
    const double perBlock = std::chrono::duration<double>(Clock::now() - blocksStart).count() /
                            double(std::max<std::size_t>(sample.size(), 1));
    const int threads = tbb::this_task_arena::max_concurrency();
    return setUp + perBlock * double(origins.size()) / double(std::max(threads, 1));
}

void SliceSums::add(const SliceSums& other) {
    all += other.all;
    foreground += other.foreground;
    marked += other.marked;
    markedForeground += other.markedForeground;
    foregroundVoxels += other.foregroundVoxels;
    markedVoxels += other.markedVoxels;
    markedForegroundVoxels += other.markedForegroundVoxels;
}

FieldAccuracy fieldAccuracyOf(const std::vector<SliceSums>& slices, const VolumeTarget& target) {
    SliceSums total;
    for (const SliceSums& slice : slices) total.add(slice);
    FieldAccuracy error;
    error.foregroundVoxels = std::uint64_t(total.foregroundVoxels);
    error.markedVoxels = std::uint64_t(total.markedVoxels);
    error.markedForegroundVoxels = std::uint64_t(total.markedForegroundVoxels);
    error.voxels = target.box().volume();
    error.mse = total.all / double(error.voxels);
    error.foregroundMse = error.foregroundVoxels > 0 ? total.foreground / double(error.foregroundVoxels) : 0.0;
    error.psnr = psnrFromMse(error.mse, target.peak());
    error.foregroundPsnr = psnrFromMse(error.foregroundMse, target.peak());
    if (error.markedVoxels > 0 && error.markedVoxels < error.voxels) {
        error.markedMse = total.marked / double(error.markedVoxels);
        error.unmarkedMse = (total.all - total.marked) / double(error.voxels - error.markedVoxels);
        error.markedPsnr = psnrFromMse(error.markedMse, target.peak());
        error.unmarkedPsnr = psnrFromMse(error.unmarkedMse, target.peak());
    }
    if (error.markedForegroundVoxels > 0 && error.markedForegroundVoxels < error.foregroundVoxels) {
        const double unmarkedSum = total.foreground - total.markedForeground;
        const double unmarkedVoxels = total.foregroundVoxels - total.markedForegroundVoxels;
        error.markedForegroundPsnr = psnrFromMse(total.markedForeground / total.markedForegroundVoxels, target.peak());
        error.unmarkedForegroundPsnr = psnrFromMse(unmarkedSum / unmarkedVoxels, target.peak());
    }
    return error;
}

FieldAccuracy measureFieldAccuracy(const GaussianField& field, const VolumeTarget& target, const ProgressFn& progress,
                                   const VoxelMarking& marked, const ThresholdCut& cut) {
    return fieldAccuracyOf(measureSliceSums(field, target, target.box(), progress, marked, cut), target);
}

}  // namespace gvr
