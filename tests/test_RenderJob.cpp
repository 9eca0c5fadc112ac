// The render job: the renderer a request names draws the frame, exactly as that
// renderer alone would, and styles are refused where they cannot be drawn.

#include "pipeline/Error.h"
#include "render/Camera.h"
#include "tests/TestHelpers.h"
#include "workflow/RenderJob.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

RenderInput ballInput() {
    RenderInput input;
    input.volume = std::make_unique<GridRenderVolume>(test::makeGrid({16, 16, 16}, [](int i, int j, int k) {
        const double r2 = (i - 8.0) * (i - 8.0) + (j - 8.0) * (j - 8.0) + (k - 8.0) * (k - 8.0);
        return float(10.0 + 100.0 * std::exp(-r2 / 20.0));
    }));
    return input;
}

OrthoCamera cameraFor(const RenderVolume& volume) {
    return makeCamera({30.0, 15.0}, worldCorners(volume.worldFromIndex(), volume.box()), 40, 32);
}

TEST(RenderJob, RenderersGoByTheirCommandLineNames) {
    EXPECT_EQ(rendererNamed("shear-warp"), RendererKind::ShearWarp);
    EXPECT_EQ(rendererNamed("raymarch"), RendererKind::RayMarch);
    EXPECT_FALSE(rendererNamed("Raymarch"));
}

TEST(RenderJob, EachRendererDrawsAsItDoesAlone) {
    const RenderInput input = ballInput();
    const Classifier classifier = classifierFor("mri", *input.volume);
    const OrthoCamera camera = cameraFor(*input.volume);
    RenderRequest request;
    FrameStats stats;
    const Framebuffer sheared = RenderJob(input, classifier, request).render(camera, stats);
    EXPECT_EQ(sheared.rgba, ShearWarpRenderer(*input.volume, classifier, request.shearWarp).render(camera).rgba);
    request.renderer = RendererKind::RayMarch;
    request.rayMarch.stepVoxels = 0.25;
    const Framebuffer marched = RenderJob(input, classifier, request).render(camera, stats);
    EXPECT_EQ(marched.rgba, rayMarch(*input.volume, classifier, camera, request.rayMarch).rgba);
    EXPECT_NE(marched.rgba, sheared.rgba);
    EXPECT_GT(stats.totalMs, 0.0);
}

TEST(RenderJob, RefusesInvalidSettingsAndStylesOfAGrid) {
    RenderRequest request;
    request.rayMarch.raysPerSide = 2;
    EXPECT_NE(request.validate().find("`samples` applies to the ray marcher"), std::string::npos);
    request.renderer = RendererKind::RayMarch;
    EXPECT_EQ(request.validate(), "");
    request.rayMarch.stepVoxels = 0.005;
    EXPECT_NE(request.validate().find("`step` must be in [0.01, 0.5]"), std::string::npos);

    const RenderInput input = ballInput();
    RenderRequest styled;
    styled.labelStyles["Left"] = LabelStyle{};
    styled.labelStylesName = "style.json";
    const std::string message =
        test::errorMessageOf<InputError>([&] { RenderJob(input, classifierFor("mri", *input.volume), styled); });
    EXPECT_NE(message.find("style.json: styles the structures of a Gaussian asset"), std::string::npos) << message;
}

}  // namespace
}  // namespace gvr
