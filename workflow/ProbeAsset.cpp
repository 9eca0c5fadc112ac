#include "workflow/ProbeAsset.h"

#include "pipeline/Trilinear.h"

namespace gvr {

namespace {

bool insideVolume(const FloatVolume& volume, const openvdb::Coord& voxel) {
    return voxel.x() >= 0 && voxel.y() >= 0 && voxel.z() >= 0 && voxel.x() < volume.dims.x() &&
           voxel.y() < volume.dims.y() && voxel.z() < volume.dims.z();
}

/// @a volume trilinear at @a index, its voxels beyond its box holding @a background.
std::array<double, 3> valueAt(const FloatVolume& volume, const std::array<double, 3>& index, double background) {
    std::array<double, 3> value{};
    const openvdb::Vec3d x(index[0], index[1], index[2]);
    const bool reaches = x[0] > -1.0 && x[1] > -1.0 && x[2] > -1.0 && x[0] < volume.dims.x() &&
                         x[1] < volume.dims.y() && x[2] < volume.dims.z();
    if (!reaches) {  // far points would also overflow a voxel's int indices
        value.fill(background);
        return value;
    }
    forEachTrilinearCorner(x, [&](const openvdb::Coord& voxel, double weight) {
        const float* sample = insideVolume(volume, voxel) ? volume.at(voxel.x(), voxel.y(), voxel.z()) : nullptr;
        for (int c = 0; c < volume.channels; ++c) value[c] += weight * (sample ? sample[c] : background);
    });
    return value;
}

}  // namespace

std::vector<AssetProbe::Sample> probeAsset(const GaussianAsset& asset, const std::vector<std::array<double, 3>>& points,
                                           AssetLayers layers, const std::string& name, const ProgressFn& progress) {
    AssetProbe field(asset);
    std::vector<AssetProbe::Sample> samples;
    samples.reserve(points.size());
    for (const auto& point : points) samples.push_back(field.at(point));
    if (!readsResidualLayer(asset, layers) || points.empty()) return samples;
    const FloatVolume reconstruction = boundedReconstruction(asset, name, progress);
    for (std::size_t n = 0; n < points.size(); ++n) {
        samples[n].value = valueAt(reconstruction, points[n], asset.source.background);
    }
    return samples;
}

}  // namespace gvr
