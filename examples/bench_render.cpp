// Render benchmark: the Render issue's comparisons, all measured in one run on one
// Gaussian asset and the grid it was fitted to, at 512 x 512.
//
//   build/cli/gvr ingest ../shared/data/ct-head-visible-human-png -o out/ct-head.vdb
//   build/cli/gvr fit out/ct-head.vdb -o out/ct-head.gvr --ratio 40 --time 120
//   build/examples/bench_render out/ct-head.gvr out/ct-head.vdb
//
// Prints: frames per second of shear-warp frames that reuse the stack, stack
// rebuild time, Gaussian shear-warp against our ray marcher on the original grid
// (time ratio at the image quality it reaches), and frames per second against
// VolPack (Lacroute's shear-warp) rendering the same volume in the same run.
// Figures are printed, never asserted.

#include "AssetFile.h"
#include "Fitter.h"
#include "GridFile.h"
#include "QualityMetrics.h"
#include "RayMarcher.h"
#include "ShearWarp.h"
#include "VolPackReference.h"

#include <chrono>
#include <cstdio>
#include <iostream>

namespace gvr {
namespace {

constexpr int kSize = 512;
constexpr double kElevation = 15.0;
constexpr int kReuseFrames = 25;  // azimuth -12..12 degrees, inside the 15 degree cone

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

OrthoCamera cameraAt(const RenderVolume& volume, double azimuth) {
    return makeCamera({azimuth, kElevation}, worldCorners(volume.worldFromIndex(), volume.box()), kSize, kSize);
}

struct ShearWarpFigures {
    double rebuildMs = 0, reuseMs = 0;
    std::vector<Framebuffer> reuseImages;  // at azimuths -12, -6, 0, 6, 12
};

ShearWarpFigures measureShearWarp(const RenderVolume& volume, const Classifier& classifier) {
    ShearWarpFigures figures;
    for (double azimuth : {0.0, 40.0, 80.0}) {
        ShearWarpRenderer renderer(volume, classifier, ShearWarpSettings{});
        FrameStats stats;
        renderer.render(cameraAt(volume, azimuth), &stats);
        figures.rebuildMs += stats.buildMs / 3.0;
    }
    ShearWarpRenderer renderer(volume, classifier, ShearWarpSettings{});
    renderer.render(cameraAt(volume, 0.0));
    for (int f = 0; f < kReuseFrames; ++f) {
        const double azimuth = -12.0 + f;
        FrameStats stats;
        Framebuffer image = renderer.render(cameraAt(volume, azimuth), &stats);
        if (!stats.reused) std::cerr << "unexpected rebuild at " << azimuth << "\n";
        figures.reuseMs += stats.totalMs / kReuseFrames;
        if (f % 6 == 0) figures.reuseImages.push_back(std::move(image));
    }
    return figures;
}

double imagePsnr(const Framebuffer& a, const Framebuffer& b) {
    return psnrFromMse(meanSquaredError(asVolume(a), asVolume(b)), 1.0);
}

/// Ray-marches the original grid at the reuse views and compares: time against the
/// Gaussian shear-warp's reused frames, and render PSNR of both the Gaussian and the
/// dense-grid shear-warp (which separates the fit's error from the renderer's).
void compareWithRayMarching(const char* label, const GridRenderVolume& original, const Classifier& classifier,
                            const ShearWarpFigures& ours) {
    const ShearWarpFigures dense = measureShearWarp(original, classifier);
    double marchMs = 0.0, gaussianDb = 0.0, denseDb = 0.0, worstDb = INFINITY;
    for (int v = 0; v < 5; ++v) {
        const auto start = std::chrono::steady_clock::now();
        const Framebuffer reference = rayMarch(original, classifier, cameraAt(original, -12.0 + 6 * v), {});
        marchMs += msSince(start) / 5;
        const double db = imagePsnr(ours.reuseImages[v], reference);
        worstDb = std::min(worstDb, db);
        gaussianDb += db / 5;
        denseDb += imagePsnr(dense.reuseImages[v], reference) / 5;
    }
    std::printf("%s classification: ray marcher on the original grid (step 0.5 voxel, early termination, VDB "
                "skipping) %.0f ms a frame\n", label, marchMs);
    std::printf("   Gaussian shear-warp (reusing, %.1f ms) is %.2fx faster at %.1f dB mean, %.1f dB worst render PSNR "
                "(target >= 3x at >= 35 dB)\n", ours.reuseMs, marchMs / ours.reuseMs, gaussianDb, worstDb);
    std::printf("   dense-grid shear-warp (reusing %.1f ms, rebuild %.0f ms): %.1f dB mean, the renderer's own error\n\n",
                dense.reuseMs, dense.rebuildMs, denseDb);
}

VolPackVolume denseBytes(const openvdb::FloatGrid& grid, const openvdb::CoordBBox& box) {
    VolPackVolume volume{box.dim().x(), box.dim().y(), box.dim().z(), {}, {1, 1, 1}};
    const openvdb::Vec3d spacing = grid.voxelSize();
    for (int a = 0; a < 3; ++a) volume.spacingMm[a] = spacing[a];
    volume.voxels.resize(std::size_t(volume.nx) * volume.ny * volume.nz);
    auto accessor = grid.getConstAccessor();
    std::size_t n = 0;
    for (int k = 0; k < volume.nz; ++k) {
        for (int j = 0; j < volume.ny; ++j) {
            for (int i = 0; i < volume.nx; ++i) {
                const float v = accessor.getValue(box.min().offsetBy(i, j, k));
                volume.voxels[n++] = std::uint8_t(std::clamp(v, 0.0f, 255.0f));
            }
        }
    }
    return volume;
}

int run(const std::string& assetPath, const std::string& gridPath) {
    initializeOpenVdb();
    const GaussianAsset asset = readAsset(assetPath);
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(chooseVolumeGrid(*readGridFile(gridPath), gridPath));
    if (!grid) throw std::runtime_error(gridPath + ": the benchmark takes a grey (float) grid");
    const GaussianRenderVolume gaussians(asset);
    const GridRenderVolume original(grid);
    // Surface-like, as VolPack's classification below: opaque soon above the air.
    const Classifier classifier(TransferFunction({{20.0, {0.90f, 0.80f, 0.70f, 0.0f}},
                                                  {60.0, {0.95f, 0.90f, 0.85f, 0.9f}},
                                                  {255.0, {1.0f, 1.0f, 1.0f, 1.0f}}}, "bench"), 1);
    std::printf("gvr render benchmark at %dx%d: %zu Gaussians from %s; grid %s; 2 threads\n"
                "transfer function: opacity 0 at 20, 0.9 at 60, 1 at 255 (of 255), per voxel\n\n", kSize, kSize,
                asset.params.count(), assetPath.c_str(), gridPath.c_str());

    const ShearWarpFigures ours = measureShearWarp(gaussians, classifier);
    std::printf("Gaussian shear-warp, frames reusing the stack: %.1f ms = %.1f FPS (target >= 30)\n", ours.reuseMs,
                1000.0 / ours.reuseMs);
    std::printf("Gaussian shear-warp, stack rebuild: %.0f ms (target <= 500)\n\n", ours.rebuildMs);
    compareWithRayMarching("surface", original, classifier, ours);
    const Classifier translucent(TransferFunction({{40.0, {0, 0, 0, 0}}, {250.0, {1, 1, 1, 0.12f}}}, "bench"), 1);
    compareWithRayMarching("translucent (opacity 0 at 40 to 0.12 at 250)", original, translucent,
                           measureShearWarp(gaussians, translucent));

    const VolPackResult volpack = renderWithVolPack(denseBytes(*grid, original.box()), kSize, kSize, kReuseFrames, 1.0,
                                                    kElevation);
    std::printf("VolPack (one thread; opacity ramp 0..24 of 255, gradient-weighted, min voxel opacity 0.05, "
                "termination 0.95): %.1f FPS after a %.2f s classification\n", volpack.framesPerSecond,
                volpack.classifySeconds);
    std::printf("Gaussian shear-warp over VolPack: %.2fx the frames per second (each with its own classification)\n",
                (1000.0 / ours.reuseMs) / volpack.framesPerSecond);
    return 0;
}

}  // namespace
}  // namespace gvr

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: bench_render ASSET GRID.vdb (see the comment at the top of bench_render.cpp)\n";
        return 2;
    }
    try {
        return gvr::run(argv[1], argv[2]);
    } catch (const std::exception& error) {
        std::cerr << "bench_render: " << error.what() << "\n";
        return 1;
    }
}
