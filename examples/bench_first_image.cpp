// First-image benchmark: what `gvr view` does before its window shows anything, and
// then until its first picture, without a window (issue 35: 0.3 s from the window).
//
//   build/examples/bench_first_image out/chest-400k.gvr [repeats]
//
// Prints the set-up (reading, the classifier with its percentiles) once, then for
// each repeat a fresh session at gvr view's settings, 512 x 512: its first frame (the
// coarse preview stack, built at once, for an asset straight from its Gaussians, and
// one composite); the refined frame, drawing frames meanwhile as the window does; and,
// once the view rests, how long its still takes (built in the background, then
// drawn). A repeat reuses what the set-up evaluated, as the window does. Figures are
// printed, never asserted.

#include "render/ViewSession.h"
#include "workflow/RenderInput.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <thread>

namespace gvr {
namespace {

constexpr int kSize = 512;

int run(const std::string& path, int repeats) {
    auto start = std::chrono::steady_clock::now();
    const RenderInput input =
        loadRenderInput(path, "", "", AssetLayers::All, ShearWarpSettings{}.minimumFootprintVoxels(), {});
    const double readMs = millisecondsSince(start);
    start = std::chrono::steady_clock::now();
    auto scene = std::make_shared<StyledLayers>();
    scene->layers.push_back({input.volume.get(), classifierFor("", *input.volume)});
    const double classifyMs = millisecondsSince(start);
    std::printf("%s: read %.0f ms, classifier %.0f ms\n", path.c_str(), readMs, classifyMs);

    const OrthoCamera camera =
        makeCamera({30.0, 15.0}, worldCorners(input.volume->worldFromIndex(), input.volume->box()), kSize, kSize);
    ShearWarpSettings moving;  // gvr view's: one sample a pixel
    moving.supersampling = 1.0;
    const ShearWarpSettings still = stillSettingsFor(moving, ShearWarpSettings{}.supersampling);
    for (int r = 0; r < repeats; ++r) {
        ViewSession session(scene, moving, Prefetch::None, FirstImage::CoarseFirst, still);
        start = std::chrono::steady_clock::now();
        FrameStats frame;
        session.render(camera, &frame);
        const double firstMs = millisecondsSince(start);
        std::printf("first image %.1f ms (coarse build %.1f ms, %zu Gaussians touched)", firstMs, frame.buildMs,
                    frame.gaussiansTouched);
        while (frame.stale) session.render(camera, &frame);
        std::printf(", refined %.1f ms", millisecondsSince(start));
        start = std::chrono::steady_clock::now();
        session.refineAtRest(camera);
        while (!session.stillToDraw(camera)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        session.render(camera, &frame);
        std::printf("; at rest, the still after %.1f ms (build %.1f ms)\n", millisecondsSince(start), frame.buildMs);
    }
    return 0;
}

}  // namespace
}  // namespace gvr

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: bench_first_image INPUT [repeats]\n");
        return 2;
    }
    try {
        return gvr::run(argv[1], argc > 2 ? std::atoi(argv[2]) : 5);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "bench_first_image: %s\n", error.what());
        return 1;
    }
}
