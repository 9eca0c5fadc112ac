#include "VolumeError.h"

#include "Fitter.h"

#include <tbb/parallel_for.h>

namespace gvr {

namespace {

SliceError measureSlice(const GaussianField& field, const VolumeTarget& target, const openvdb::CoordBBox& box, int z,
                        const VoxelMarking& marked, const ThresholdCut& cut) {
    const int channels = target.channels();
    SliceError error;
    std::vector<std::uint32_t> hits;
    float value[3], expected[3];
    for (int y = box.min().y(); y <= box.max().y(); ++y) {
        for (int x = box.min().x(); x <= box.max().x(); ++x) {
            const openvdb::Coord ijk(x, y, z);
            const float point[3] = {float(x), float(y), float(z)};
            field.evaluate(point, value, hits);
            cut.apply(value);
            target.valueAt(ijk, expected);
            double squared = 0.0;
            for (int c = 0; c < channels; ++c) squared += double(value[c] - expected[c]) * (value[c] - expected[c]);
            squared /= channels;
            error.all += squared;
            const bool active = target.isActive(ijk);
            if (active) {
                error.foreground += squared;
                ++error.foregroundVoxels;
            }
            if (marked && marked(ijk)) {
                error.marked += squared;
                ++error.markedVoxels;
                if (active) {
                    error.markedForeground += squared;
                    ++error.markedForegroundVoxels;
                }
            }
        }
    }
    return error;
}

}  // namespace

std::vector<SliceError> measureSliceErrors(const GaussianField& field, const VolumeTarget& target,
                                           openvdb::CoordBBox part, const ProgressFn& progress,
                                           const VoxelMarking& marked, const ThresholdCut& cut) {
    part.intersect(target.box());
    std::vector<SliceError> slices(part.empty() ? 0 : std::size_t(part.dim().z()));
    ProgressCounter counter(progress, slices.size());
    tbb::parallel_for(0, int(slices.size()), [&](int s) {
        slices[s] = measureSlice(field, target, part, part.min().z() + s, marked, cut);
        counter.advance();
    });
    return slices;
}

void SliceError::add(const SliceError& other) {
    all += other.all;
    foreground += other.foreground;
    marked += other.marked;
    markedForeground += other.markedForeground;
    foregroundVoxels += other.foregroundVoxels;
    markedVoxels += other.markedVoxels;
    markedForegroundVoxels += other.markedForegroundVoxels;
}

VolumeError volumeErrorOf(const std::vector<SliceError>& slices, const VolumeTarget& target) {
    SliceError total;
    for (const SliceError& slice : slices) total.add(slice);
    VolumeError error;
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

VolumeError measureVolumeError(const GaussianField& field, const VolumeTarget& target, const ProgressFn& progress,
                               const VoxelMarking& marked, const ThresholdCut& cut) {
    return volumeErrorOf(measureSliceErrors(field, target, target.box(), progress, marked, cut), target);
}

}  // namespace gvr
