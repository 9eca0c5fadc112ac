#include "render/RayMarcher.h"

#include "pipeline/Error.h"

#include <openvdb/tools/RayIntersector.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>
#include <utility>

namespace gvr {

using openvdb::Vec3d;

namespace {

template <typename GridT>
void marchGrid(const GridT& grid, const RenderVolume& volume, const Classifier& classifier, const OrthoCamera& camera,
               const RayMarchSettings& settings, Framebuffer& image) {
    using Ray = openvdb::math::Ray<double>;
    if (grid.activeVoxelCount() == 0) return;
    // The intersector wants uniform voxels; rays here are in index space, so a
    // shallow copy of the grid with a unit transform serves any voxel shape.
    typename GridT::ConstPtr indexGrid = grid.copy();
    std::const_pointer_cast<GridT>(indexGrid)->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
    // One voxel of dilation: trilinear samples reach a voxel beyond the active ones.
    const openvdb::tools::VolumeRayIntersector<GridT, 0> master(*indexGrid, /*dilationCount=*/1);

    const openvdb::math::Mat4d indexFromWorld = volume.worldFromIndex().inverse();
    const Vec3d indexDirection = indexFromWorld.transform3x3(camera.direction);
    const double indexPerMm = indexDirection.length();
    const Vec3d unitDirection = indexDirection / indexPerMm;
    const double lengthRatio = std::max(settings.stepVoxels, volume.finestStepVoxels(camera.direction));
    const double step = lengthRatio * volume.voxelMm() * indexPerMm;  // in index-space length along the ray
    // Inactive space holds the background: skip it only where the classification
    // makes the background transparent, as shear-warp does.
    const bool skipEmpty = classifier.transferFunction()(volume.backgroundKey())[3] == 0.0f;
    // Rays sample only inside the volume's cells: nothing exists outside them.
    const openvdb::BBoxd cells(volume.box().min().asVec3d() - Vec3d(0.5), volume.box().max().asVec3d() + Vec3d(0.5));
    double reach = 0.0;  // how far behind the image plane rays must start
    for (const Vec3d& c : worldCorners(volume.worldFromIndex(), volume.box()))
        reach = std::max(reach, (c - camera.centre).length());

    // Rays at the centres of an n x n grid over each pixel, averaged.
    const int n = settings.raysPerSide;
    const double weight = 1.0 / double(n * n);
    tbb::parallel_for(0, camera.height, [&](int y) {
        openvdb::tools::VolumeRayIntersector<GridT, 0> intersector(master);
        auto accessor = grid.getConstAccessor();
        const auto march = [&](double px, double py, float ray[4]) {
            const Vec3d eye = indexFromWorld.transform(camera.pixelPoint(px, py) - camera.direction * reach);
            Ray indexRay(eye, unitDirection);
            if (!indexRay.clip(cells)) return;
            const double enter = indexRay.t0(), exit = indexRay.t1();
            if (skipEmpty && !intersector.setIndexRay(indexRay)) return;
            double t0 = enter, t1 = exit;
            bool whole = !skipEmpty;  // one interval, the whole crossing, when nothing may be skipped
            while (ray[3] < settings.terminationOpacity &&
                   (std::exchange(whole, false) || (skipEmpty && intersector.march(t0, t1)))) {
                t0 = std::max(t0, enter);
                t1 = std::min(t1, exit);
                // Samples sit on one comb along the whole ray, so intervals never shift them.
                for (double t = std::ceil(t0 / step - 0.5) * step + 0.5 * step; t < t1; t += step) {
                    float value[3];
                    GridRenderVolume::trilinear(accessor, eye + unitDirection * t, value);
                    const std::array<float, 4> rgba = classifier(value);
                    const float alpha = opacityOverLength(rgba[3], lengthRatio);
                    if (alpha <= 0.0f) continue;
                    const float transmit = 1.0f - ray[3];
                    for (int c = 0; c < 3; ++c) ray[c] += transmit * alpha * rgba[c];
                    ray[3] += transmit * alpha;
                    if (ray[3] >= settings.terminationOpacity) break;
                }
            }
        };
        for (int x = 0; x < camera.width; ++x) {
            float* pixel = image.pixel(x, y);
            double sum[4] = {0, 0, 0, 0};
            for (int sy = 0; sy < n; ++sy) {
                for (int sx = 0; sx < n; ++sx) {
                    float ray[4] = {0, 0, 0, 0};
                    march(x - 0.5 + (sx + 0.5) / n, y - 0.5 + (sy + 0.5) / n, ray);
                    for (int c = 0; c < 4; ++c) sum[c] += ray[c];
                }
            }
            for (int c = 0; c < 4; ++c) pixel[c] = float(weight * sum[c]);
        }
    });
}

}  // namespace

Framebuffer rayMarch(const RenderVolume& volume, const Classifier& classifier, const OrthoCamera& camera,
                     const RayMarchSettings& settings) {
    if (settings.raysPerSide < 1 || settings.raysPerSide > kMaxRaysPerSide) {
        throw InputError("`samples`",
                         "must be 1 to " + std::to_string(kMaxRaysPerSide) + " rays along each side of a pixel");
    }
    Framebuffer image(camera.width, camera.height);
    if (const auto* grey = dynamic_cast<const openvdb::FloatGrid*>(&volume.voxels())) {
        marchGrid(*grey, volume, classifier, camera, settings, image);
    } else {
        marchGrid(dynamic_cast<const openvdb::Vec3SGrid&>(volume.voxels()), volume, classifier, camera, settings,
                  image);
    }
    return image;
}

}  // namespace gvr
