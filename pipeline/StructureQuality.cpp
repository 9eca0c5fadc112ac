#include "pipeline/StructureQuality.h"

#include "pipeline/Fitter.h"

namespace gvr {

namespace {

/// The box of @a volume's voxels labelled @a id, with the rest of the box zeroed.
FloatVolume cutOut(const FloatVolume& volume, const std::vector<int>& labels, int id, const openvdb::CoordBBox& box) {
    FloatVolume out(box.dim(), volume.channels);
    for (int k = box.min().z(); k <= box.max().z(); ++k) {
        for (int j = box.min().y(); j <= box.max().y(); ++j) {
            for (int i = box.min().x(); i <= box.max().x(); ++i) {
                if (labels[volume.indexOf(i, j, k)] != id) continue;
                const float* from = volume.at(i, j, k);
                float* to = out.at(i - box.min().x(), j - box.min().y(), k - box.min().z());
                for (int c = 0; c < volume.channels; ++c) to[c] = from[c];
            }
        }
    }
    return out;
}

}  // namespace

std::vector<StructureQuality> structureQuality(const FloatVolume& reference, const FloatVolume& test,
                                               const std::vector<int>& labels, const std::vector<int>& ids,
                                               double peak) {
    SsimSettings settings;
    settings.dataRange = peak;
    std::vector<StructureQuality> result;
    for (int id : ids) {
        StructureQuality q;
        q.id = id;
        std::vector<std::uint8_t> mask(labels.size());
        openvdb::CoordBBox box;
        for (int k = 0; k < reference.dims.z(); ++k) {
            for (int j = 0; j < reference.dims.y(); ++j) {
                for (int i = 0; i < reference.dims.x(); ++i) {
                    const std::size_t n = reference.indexOf(i, j, k);
                    if (labels[n] != id) continue;
                    mask[n] = 1;
                    box.expand(openvdb::Coord(i, j, k));
                    ++q.voxels;
                }
            }
        }
        if (q.voxels > 0) {
            q.mse = meanSquaredError(reference, test, mask);
            q.psnr = psnrFromMse(q.mse, peak);
            q.ssim = ssim(cutOut(reference, labels, id, box), cutOut(test, labels, id, box), settings);
        }
        result.push_back(q);
    }
    return result;
}

}  // namespace gvr
