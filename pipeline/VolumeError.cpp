#include "VolumeError.h"

#include "Fitter.h"

#include <tbb/parallel_for.h>

namespace gvr {

VolumeError measureVolumeError(const GaussianField& field, const VolumeTarget& target,
                               const ProgressFn& progress, const VoxelMarking& marked) {
    const openvdb::CoordBBox& box = target.box();
    const int slices = box.dim().z();
    const int channels = target.channels();
    std::vector<double> all(slices, 0.0), foreground(slices, 0.0);
    std::vector<double> markedSum(slices, 0.0);
    std::vector<std::uint64_t> foregroundCount(slices, 0), markedCount(slices, 0);
    ProgressCounter counter(progress, std::size_t(slices));
    tbb::parallel_for(0, slices, [&](int slice) {
        std::vector<std::uint32_t> hits;
        float value[3], expected[3];
        const int z = box.min().z() + slice;
        for (int y = box.min().y(); y <= box.max().y(); ++y) {
            for (int x = box.min().x(); x <= box.max().x(); ++x) {
                const openvdb::Coord ijk(x, y, z);
                const float point[3] = {float(x), float(y), float(z)};
                field.evaluate(point, value, hits);
                target.valueAt(ijk, expected);
                double squared = 0.0;
                for (int c = 0; c < channels; ++c) squared += double(value[c] - expected[c]) * (value[c] - expected[c]);
                squared /= channels;
                all[slice] += squared;
                if (target.isActive(ijk)) {
                    foreground[slice] += squared;
                    ++foregroundCount[slice];
                }
                if (marked && marked(ijk)) {
                    markedSum[slice] += squared;
                    ++markedCount[slice];
                }
            }
        }
        counter.advance();
    });
    VolumeError error;
    double sumAll = 0.0, sumForeground = 0.0, sumMarked = 0.0;
    for (int s = 0; s < slices; ++s) {
        sumAll += all[s];
        sumForeground += foreground[s];
        sumMarked += markedSum[s];
        error.foregroundVoxels += foregroundCount[s];
        error.markedVoxels += markedCount[s];
    }
    error.voxels = box.volume();
    error.mse = sumAll / double(error.voxels);
    error.foregroundMse = error.foregroundVoxels > 0 ? sumForeground / double(error.foregroundVoxels) : 0.0;
    error.psnr = psnrFromMse(error.mse, target.peak());
    error.foregroundPsnr = psnrFromMse(error.foregroundMse, target.peak());
    if (error.markedVoxels > 0 && error.markedVoxels < error.voxels) {
        error.markedMse = sumMarked / double(error.markedVoxels);
        error.unmarkedMse = (sumAll - sumMarked) / double(error.voxels - error.markedVoxels);
        error.markedPsnr = psnrFromMse(error.markedMse, target.peak());
        error.unmarkedPsnr = psnrFromMse(error.unmarkedMse, target.peak());
    }
    return error;
}

}  // namespace gvr
