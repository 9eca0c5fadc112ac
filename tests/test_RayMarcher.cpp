// The reference renderer's rays per pixel: many rays are one ray at a finer pixel
// pitch, averaged, and they soften what one ray aliases.

#include "pipeline/Error.h"
#include "render/RayMarcher.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

/// A box of rising values on a transparent surround, seen at an angle.
struct SlabScene {
    GridRenderVolume slab{test::makeGrid({24, 16, 8}, [](int i, int, int) { return i < 6 ? 0.0f : 25.0f * i; })};
    Classifier classifier{TransferFunction({{100.0, {0.2f, 0.2f, 0.9f, 0.0f}}, {500.0, {1, 1, 1, 0.4f}}}, "test"), 1};
    OrthoCamera camera = makeCamera({35, 25}, worldCorners(slab.worldFromIndex(), slab.box()), 24, 20);
};

Framebuffer march(const SlabScene& scene, const OrthoCamera& camera, int raysPerSide) {
    RayMarchSettings settings;
    settings.raysPerSide = raysPerSide;
    return rayMarch(scene.slab, scene.classifier, camera, settings);
}

TEST(RayMarcher, ManyRaysAreOneRayAtAFinerPitchAveraged) {
    const SlabScene scene;
    const int n = kReferenceRaysPerSide;
    OrthoCamera fine = scene.camera;
    fine.width *= n;
    fine.height *= n;
    fine.pixelMm /= n;
    const Framebuffer averaged = march(scene, scene.camera, n);
    const Framebuffer detailed = march(scene, fine, 1);
    double largest = 0.0;
    for (int y = 0; y < scene.camera.height; ++y) {
        for (int x = 0; x < scene.camera.width; ++x) {
            for (int c = 0; c < 4; ++c) {
                double mean = 0.0;
                for (int sy = 0; sy < n; ++sy) {
                    for (int sx = 0; sx < n; ++sx) mean += detailed.pixel(n * x + sx, n * y + sy)[c];
                }
                mean /= n * n;
                EXPECT_NEAR(averaged.pixel(x, y)[c], mean, 1e-5) << "pixel " << x << ", " << y << ", channel " << c;
                largest = std::max(largest, mean);
            }
        }
    }
    EXPECT_GT(largest, 0.5);  // the scene is not empty
}

TEST(RayMarcher, ManyRaysSoftenTheSilhouette) {
    const SlabScene scene;
    const Framebuffer one = march(scene, scene.camera, 1), many = march(scene, scene.camera, kReferenceRaysPerSide);
    // Coverage between none and full: along the silhouette, where one ray can only hit or miss.
    const auto partial = [](const Framebuffer& image) {
        int count = 0;
        for (std::size_t p = 3; p < image.rgba.size(); p += 4) count += image.rgba[p] > 0.02f && image.rgba[p] < 0.5f;
        return count;
    };
    EXPECT_GT(partial(many), partial(one) + 10);
    EXPECT_NEAR(test::opacitySum(many) / test::opacitySum(one), 1.0, 0.1);  // the same object, only its edge resolved
}

TEST(RayMarcher, RefusesRayCountsOutOfRange) {
    const SlabScene scene;
    for (int n : {0, -1, kMaxRaysPerSide + 1}) {
        const std::string message = test::errorMessageOf<InputError>([&] { march(scene, scene.camera, n); });
        EXPECT_NE(message.find("`samples`"), std::string::npos) << message;
    }
}

}  // namespace
}  // namespace gvr
