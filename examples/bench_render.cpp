// Render benchmark: the Render issue's comparisons, all measured in one run on one
// Gaussian asset and the grid it was fitted to, at 512 x 512.
//
//   build/cli/gvr ingest ../shared/data/ct-head-visible-human-png -o out/ct-head.vdb
//   build/cli/gvr fit out/ct-head.vdb -o out/ct-head.gvr --ratio 40 --time 120
//   build/examples/bench_render out/ct-head.gvr out/ct-head.vdb
//
// Prints, for a surface and a translucent classification: frames per second of
// shear-warp frames that reuse the stack and stack build times, with axis and view
// stacks, supersampled and not, and axis stacks at one sample a voxel as VolPack
// samples; Gaussian and dense-grid shear-warp against the anti-aliased ray marcher
// (4 x 4 rays a pixel, averaged) on the Gaussians' export and on the original grid
// (render PSNR as seen), against which the one-ray ray marcher is measured too (the
// figure to reach); Gaussian shear-warp against the one-ray ray marcher on the
// original grid; and frames per second against VolPack
// (Lacroute's shear-warp) with the same opacities per voxel, in the same run.
// The asset's voxels are evaluated once, by its first reference; the Gaussian
// builds timed here read them, as every build after an asset's first does.
// Figures are printed, never asserted.

#include "examples/VolPackReference.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "pipeline/Fitter.h"
#include "pipeline/QualityMetrics.h"
#include "render/RayMarcher.h"
#include "render/ShearWarp.h"
#include "workflow/Evaluate.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

namespace gvr {
namespace {

constexpr int kSize = 512;
constexpr double kElevation = 15.0;
constexpr int kReuseFrames = 25;  // azimuth -12..12 degrees: one axis stack, or one view stack's cone

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

OrthoCamera cameraAt(const RenderVolume& volume, double azimuth) {
    return makeCamera({azimuth, kElevation}, worldCorners(volume.worldFromIndex(), volume.box()), kSize, kSize);
}

/// The anti-aliased reference: the ray marcher with kReferenceRaysPerSide^2 rays a pixel.
Framebuffer rayMarchAntialiased(const RenderVolume& volume, const Classifier& classifier, double azimuth) {
    RayMarchSettings settings;
    settings.raysPerSide = kReferenceRaysPerSide;
    return rayMarch(volume, classifier, cameraAt(volume, azimuth), settings);
}

const char* nameOf(StackOrientation orientation) { return orientation == StackOrientation::Axes ? "axis" : "view"; }

struct ShearWarpFigures {
    double rebuildMs = 0, reuseMs = 0;
    std::vector<Framebuffer> reuseImages;  // at azimuths -12, -6, 0, 6, 12
};

ShearWarpFigures measureShearWarp(const RenderVolume& volume, const Classifier& classifier,
                                  const ShearWarpSettings& settings) {
    ShearWarpFigures figures;
    for (double azimuth : {0.0, 40.0, 80.0}) {
        ShearWarpRenderer renderer(volume, classifier, settings);
        FrameStats stats;
        renderer.render(cameraAt(volume, azimuth), &stats);
        figures.rebuildMs += stats.buildMs / 3.0;
    }
    ShearWarpRenderer renderer(volume, classifier, settings);
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

/// Render PSNR as seen (README, Evaluate), as gvr eval and gvr bench report it.
double imagePsnr(const Framebuffer& reference, const Framebuffer& test) {
    return renderingQuality(asVolume(reference), asVolume(test)).psnr;
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

/// The classifier's opacity per voxel at each 8-bit value, as VolPack takes it.
std::vector<float> opacityByValue(const Classifier& classifier) {
    std::vector<float> table(256);
    for (int v = 0; v < 256; ++v) {
        const float value = float(v);
        table[v] = classifier(&value)[3];
    }
    return table;
}

/// Ray-marched references at the five views that reused frames keep, with one ray
/// a pixel and anti-aliased, on the original grid and on the Gaussians (their
/// voxels, as their export holds them).
struct References {
    std::vector<Framebuffer> original, gaussians, antialiased, gaussiansAntialiased;
    double marchMs = 0.0;
};

References referencesFor(const GridRenderVolume& original, const GaussianRenderVolume& gaussians,
                         const Classifier& classifier) {
    References references;
    for (int v = 0; v < 5; ++v) {
        const double azimuth = -12.0 + 6 * v;
        const auto start = std::chrono::steady_clock::now();
        references.original.push_back(rayMarch(original, classifier, cameraAt(original, azimuth), {}));
        references.marchMs += msSince(start) / 5;
        references.gaussians.push_back(rayMarch(gaussians, classifier, cameraAt(gaussians, azimuth), {}));
        references.antialiased.push_back(rayMarchAntialiased(original, classifier, azimuth));
        references.gaussiansAntialiased.push_back(rayMarchAntialiased(gaussians, classifier, azimuth));
    }
    return references;
}

/// Mean and worst render PSNR of @a images against @a references, view by view.
std::pair<double, double> meanAndWorstDb(const std::vector<Framebuffer>& references,
                                         const std::vector<Framebuffer>& images) {
    double mean = 0.0, worst = INFINITY;
    for (std::size_t v = 0; v < references.size(); ++v) {
        const double db = imagePsnr(references[v], images[v]);
        mean += db / references.size();
        worst = std::min(worst, db);
    }
    return {mean, worst};
}

/// The shear-warp settings compared: axis and view stacks, each supersampled (the
/// default) and with one sample a pixel (gvr view's default); and axis stacks with
/// one sample a voxel, as VolPack samples, @a voxelSupersampling being the pixel
/// over the voxel (at least 1).
std::vector<ShearWarpSettings> settingsCompared(double voxelSupersampling) {
    std::vector<ShearWarpSettings> all;
    for (const StackOrientation orientation : {StackOrientation::Axes, StackOrientation::View}) {
        for (const double supersampling : {ShearWarpSettings{}.supersampling, 1.0}) {
            ShearWarpSettings settings;
            settings.stacks = orientation;
            settings.supersampling = supersampling;
            all.push_back(settings);
        }
    }
    ShearWarpSettings asVolPack;
    asVolPack.stacks = StackOrientation::Axes;
    asVolPack.supersampling = voxelSupersampling;
    all.push_back(asVolPack);
    return all;
}

/// One classification: Gaussian and dense-grid shear-warp with each of
/// settingsCompared(), the ray marchers (the references), and VolPack with the same
/// opacities per voxel, all in this run.
void compare(const char* label, const GaussianRenderVolume& gaussians, const GridRenderVolume& original,
             const VolPackVolume& bytes, const Classifier& classifier) {
    std::printf("%s classification\n", label);
    const References references = referencesFor(original, gaussians, classifier);
    std::printf(
        "   ray marcher, one ray a pixel (step 0.5 voxel, early termination, VDB skipping): %.0f ms a frame; "
        "against the anti-aliased one (%d x %d rays a pixel): %.1f dB on the original grid, %.1f dB on the "
        "Gaussians' export (the targets of shear-warp's two figures against it below)\n",
        references.marchMs, kReferenceRaysPerSide, kReferenceRaysPerSide,
        meanAndWorstDb(references.antialiased, references.original).first,
        meanAndWorstDb(references.gaussiansAntialiased, references.gaussians).first);
    std::vector<double> axisReuseMs;
    const double voxelSupersampling = std::max(1.0, cameraAt(original, 0.0).pixelMm / original.voxelMm());
    for (const ShearWarpSettings& settings : settingsCompared(voxelSupersampling)) {
        const ShearWarpFigures ours = measureShearWarp(gaussians, classifier, settings);
        const ShearWarpFigures dense = measureShearWarp(original, classifier, settings);
        if (settings.stacks == StackOrientation::Axes) axisReuseMs.push_back(ours.reuseMs);
        const auto [gaussianDb, worstDb] = meanAndWorstDb(references.original, ours.reuseImages);
        std::printf("   %s stacks, supersample %.2f\n", nameOf(settings.stacks), settings.supersampling);
        std::printf(
            "      Gaussians: reused frame %.1f ms = %.1f FPS, build %.0f ms; %.1f dB mean, %.1f dB worst "
            "against the ray marcher on the original; %.1fx its speed; %.1f dB against the anti-aliased "
            "ray marcher on the Gaussians (the renderer's own error)\n",
            ours.reuseMs, 1000.0 / ours.reuseMs, ours.rebuildMs, gaussianDb, worstDb, references.marchMs / ours.reuseMs,
            meanAndWorstDb(references.gaussiansAntialiased, ours.reuseImages).first);
        std::printf(
            "      dense grid: reused frame %.1f ms, build %.0f ms; %.1f dB against the anti-aliased ray "
            "marcher (the renderer's own error)\n",
            dense.reuseMs, dense.rebuildMs, meanAndWorstDb(references.antialiased, dense.reuseImages).first);
    }
    const VolPackResult volpack =
        renderWithVolPack(bytes, kSize, kSize, kReuseFrames, 1.0, kElevation, opacityByValue(classifier));
    const auto overVolPack = [&](double reuseMs) { return (1000.0 / reuseMs) / volpack.framesPerSecond; };
    std::printf(
        "   VolPack, one thread, the same opacities per voxel: %.1f FPS after a %.2f s classification; "
        "Gaussian shear-warp (axis stacks, two threads) over VolPack: %.2fx the frames per second "
        "supersampled, %.2fx with one sample a voxel (as VolPack), %.2fx with one sample a pixel\n\n",
        volpack.framesPerSecond, volpack.classifySeconds, overVolPack(axisReuseMs[0]), overVolPack(axisReuseMs[2]),
        overVolPack(axisReuseMs[1]));
}

int run(const std::string& assetPath, const std::string& gridPath) {
    initializeOpenVdb();
    const GaussianAsset asset = readAsset(assetPath);
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(chooseVolumeGrid(*readGridFile(gridPath), gridPath));
    if (!grid) throw std::runtime_error(gridPath + ": the benchmark takes a grey (float) grid");
    const GaussianRenderVolume gaussians(asset);
    const GridRenderVolume original(grid);
    const VolPackVolume bytes = denseBytes(*grid, original.box());
    std::printf("gvr render benchmark at %dx%d: %zu Gaussians from %s; grid %s; 2 threads; render PSNR as seen\n\n",
                kSize, kSize, asset.params.count(), assetPath.c_str(), gridPath.c_str());
    // Surface-like: opaque soon above the air.
    const Classifier surface(TransferFunction({{20.0, {0.90f, 0.80f, 0.70f, 0.0f}},
                                               {60.0, {0.95f, 0.90f, 0.85f, 0.9f}},
                                               {255.0, {1.0f, 1.0f, 1.0f, 1.0f}}},
                                              "bench"),
                             1);
    compare("surface (opacity 0 at 20, 0.9 at 60, 1 at 255 of 255, per voxel)", gaussians, original, bytes, surface);
    const Classifier translucent(TransferFunction({{40.0, {0, 0, 0, 0}}, {250.0, {1, 1, 1, 0.12f}}}, "bench"), 1);
    compare("translucent (opacity 0 at 40 to 0.12 at 250)", gaussians, original, bytes, translucent);
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
