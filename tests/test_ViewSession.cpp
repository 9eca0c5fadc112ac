// The interactive session: the same frames as the renderer once settled, stale
// frames (never a wait) while a stack builds, axis stacks kept, and rebuilds on
// scene and zoom changes.

#include "render/ViewSession.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

namespace gvr {
namespace {

std::shared_ptr<GridRenderVolume> blob() {
    const auto value = [](int i, int j, int k) {
        const double x = i - 20.0, y = j - 16.0, z = k - 12.0;
        return float(1000.0 * std::exp(-(x * x / 60.0 + y * y / 20.0 + z * z / 30.0)));
    };
    return std::make_shared<GridRenderVolume>(test::makeGrid({40, 32, 24}, value));
}

Scene sceneOf(const RenderVolume& volume, float opacity) {
    auto scene = std::make_shared<StyledLayers>();
    const TransferFunction tf({{50.0, {0.2f, 0.1f, 0.0f, 0.0f}}, {1000.0, {1.0f, 0.9f, 0.7f, opacity}}}, "test");
    scene->layers.push_back({&volume, Classifier(tf, 1)});
    return scene;
}

OrthoCamera cameraFor(const RenderVolume& volume, double azimuth, double zoom = 1.0, int size = 64) {
    OrthoCamera camera = makeCamera({azimuth, 20.0}, worldCorners(volume.worldFromIndex(), volume.box()), size, size);
    camera.pixelMm /= zoom;
    return camera;
}

Framebuffer freshFrame(const Scene& scene, const OrthoCamera& camera) {
    return ShearWarpRenderer(scene->layers, ShearWarpSettings{}).render(camera);
}

TEST(ViewSession, SettledFramesAreTheRenderersFrames) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, ShearWarpSettings{});
    FrameStats first;
    EXPECT_EQ(session.render(cameraFor(*volume, 30.0), &first).rgba, freshFrame(scene, cameraFor(*volume, 30.0)).rgba);
    EXPECT_FALSE(first.stale);
    EXPECT_FALSE(first.reused);
    EXPECT_EQ(session.renderSettled(cameraFor(*volume, 75.0)).rgba, freshFrame(scene, cameraFor(*volume, 75.0)).rgba);
}

ShearWarpSettings viewStacks() {
    ShearWarpSettings settings;
    settings.stacks = StackOrientation::View;
    return settings;
}

TEST(ViewSession, CoarseFirstDrawsACoarseStackAtOnceThenTheRenderersFrame) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, ShearWarpSettings{}, Prefetch::None, FirstImage::CoarseFirst);
    const OrthoCamera camera = cameraFor(*volume, 30.0);
    FrameStats first;
    const Framebuffer coarse = session.render(camera, &first);
    EXPECT_TRUE(first.stale);
    EXPECT_FALSE(first.reused);
    EXPECT_EQ(coarse.width, camera.width);
    EXPECT_EQ(session.stacksBuilt(), 1);
    FrameStats settled;
    const Framebuffer refined = session.renderSettled(camera, &settled);
    EXPECT_FALSE(settled.stale);
    EXPECT_EQ(session.stacksBuilt(), 2);
    EXPECT_EQ(refined.rgba, freshFrame(scene, camera).rgba);
    EXPECT_NE(coarse.rgba, refined.rgba);
    // The coarse stack samples an eighth as much: the same blob, a little blurred.
    double covered[2] = {0, 0};
    for (std::size_t p = 3; p < coarse.rgba.size(); p += 4) {
        covered[0] += coarse.rgba[p];
        covered[1] += refined.rgba[p];
    }
    EXPECT_NEAR(covered[0], covered[1], 0.1 * covered[1]);
}

TEST(ViewSession, ATurnBeyondTheConeIsDrawnFromTheOldStackWhileTheNewOneBuilds) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, viewStacks());
    session.render(cameraFor(*volume, 0.0));
    FrameStats turned;
    const Framebuffer stale = session.render(cameraFor(*volume, 30.0), &turned);
    EXPECT_TRUE(turned.stale);
    EXPECT_TRUE(turned.reused);
    EXPECT_TRUE(session.building());
    FrameStats settled;
    const Framebuffer rebuilt = session.renderSettled(cameraFor(*volume, 30.0), &settled);
    EXPECT_FALSE(settled.stale);
    EXPECT_EQ(rebuilt.rgba, ShearWarpRenderer(scene->layers, viewStacks()).render(cameraFor(*volume, 30.0)).rgba);
    EXPECT_NE(stale.rgba, rebuilt.rgba);  // another stack, though the same view
}

TEST(ViewSession, AxisStacksAreKeptSoThatTurningBackBuildsNothing) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, ShearWarpSettings{});
    session.renderSettled(cameraFor(*volume, 0.0));    // along y
    session.renderSettled(cameraFor(*volume, 80.0));   // along x
    session.renderSettled(cameraFor(*volume, 200.0));  // along y, from behind
    EXPECT_EQ(session.stacksBuilt(), 2);
    FrameStats back;
    const Framebuffer image = session.render(cameraFor(*volume, 100.0), &back);  // x again
    EXPECT_FALSE(back.stale);
    EXPECT_FALSE(session.building());
    EXPECT_EQ(session.stacksBuilt(), 2);
    ShearWarpRenderer renderer(scene->layers, ShearWarpSettings{});
    renderer.render(cameraFor(*volume, 80.0));  // the x stack on the same lattice as the session's
    EXPECT_EQ(image.rgba, renderer.render(cameraFor(*volume, 100.0)).rgba);
}

TEST(ViewSession, APrefetchedNextAxisMakesCrossingToItDrawAtOnce) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, ShearWarpSettings{}, Prefetch::NextAxis);
    session.renderSettled(cameraFor(*volume, 30.0));  // along y; x is the next nearest axis
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (session.building()) {
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the prefetch never finished";
        FrameStats waiting;
        session.render(cameraFor(*volume, 30.0), &waiting);
        EXPECT_FALSE(waiting.stale);
        EXPECT_TRUE(waiting.reused);  // the prefetched stack is kept aside, not shown
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    EXPECT_EQ(session.stacksBuilt(), 2);
    FrameStats crossed;
    session.render(cameraFor(*volume, 60.0), &crossed);  // along x
    EXPECT_FALSE(crossed.stale);
    EXPECT_FALSE(session.building());  // its next axis, y, is kept
    EXPECT_EQ(session.stacksBuilt(), 2);
}

TEST(ViewSession, ANewSceneOrAZoomRebuildsTheStack) {
    const auto volume = blob();
    ViewSession session(sceneOf(*volume, 0.1f), ShearWarpSettings{});
    session.render(cameraFor(*volume, 10.0));

    const Scene denser = sceneOf(*volume, 0.6f);
    session.setScene(denser);
    FrameStats changed;
    session.render(cameraFor(*volume, 10.0), &changed);
    EXPECT_TRUE(changed.stale);
    EXPECT_EQ(session.renderSettled(cameraFor(*volume, 10.0)).rgba, freshFrame(denser, cameraFor(*volume, 10.0)).rgba);

    // A small image has pixels of several voxels; zoomed in, they shrink towards one.
    session.renderSettled(cameraFor(*volume, 10.0, 1.0, 16));
    FrameStats zoomed;
    session.render(cameraFor(*volume, 10.0, 3.0, 16), &zoomed);
    EXPECT_TRUE(zoomed.stale);
    EXPECT_EQ(session.renderSettled(cameraFor(*volume, 10.0, 3.0, 16)).rgba,
              freshFrame(denser, cameraFor(*volume, 10.0, 3.0, 16)).rgba);
    // Beyond one voxel a pixel, zooming further needs no finer stack.
    session.renderSettled(cameraFor(*volume, 10.0, 8.0, 16));
    FrameStats further;
    session.render(cameraFor(*volume, 10.0, 16.0, 16), &further);
    EXPECT_FALSE(further.stale);
}

/// A grid whose blocks wait while its gate is shut: a test holds a stack build in
/// progress for as long as it needs, whatever the machine's speed.
class GatedVolume : public RenderVolume {
public:
    explicit GatedVolume(std::shared_ptr<GridRenderVolume> grid) : mGrid(std::move(grid)) {
        mWorldFromIndex = mGrid->worldFromIndex();
        mBox = mGrid->box();
        mValueMax = mGrid->valueMax();
    }

    int channels() const override { return mGrid->channels(); }
    const openvdb::GridBase& voxels() const override { return mGrid->voxels(); }
    std::unique_ptr<BlockSource> blocksOn(const Lattice& lattice, double invisibleUpTo) const override {
        return std::make_unique<Blocks>(mGrid->blocksOn(lattice, invisibleUpTo), open);
    }
    std::array<float, 3> background() const override { return mGrid->background(); }

    std::atomic<bool> open{true};

protected:
    VolumeStatistics gatherStatistics() const override { return mGrid->statistics(); }

private:
    class Blocks : public BlockSource {
    public:
        Blocks(std::unique_ptr<BlockSource> blocks, const std::atomic<bool>& open)
            : mBlocks(std::move(blocks)), mOpen(open) {}
        std::vector<openvdb::Coord> occupiedBlocks() const override { return mBlocks->occupiedBlocks(); }
        openvdb::CoordBBox sampleBlock(const openvdb::Coord& origin, float* values) const override {
            while (!mOpen) std::this_thread::sleep_for(std::chrono::milliseconds(1));
            return mBlocks->sampleBlock(origin, values);
        }

    private:
        std::unique_ptr<BlockSource> mBlocks;
        const std::atomic<bool>& mOpen;
    };

    std::shared_ptr<GridRenderVolume> mGrid;
};

TEST(ViewSession, ABuildTheViewHasLeftIsCancelledForTheOneItNeedsNow) {
    GatedVolume volume(blob());
    const Scene scene = sceneOf(volume, 0.1f);
    const auto view = [&](double azimuth, double elevation) {
        return makeCamera({azimuth, elevation}, worldCorners(volume.worldFromIndex(), volume.box()), 64, 64);
    };
    ViewSession session(scene, ShearWarpSettings{});
    session.renderSettled(view(0.0, 20.0));  // along y
    volume.open = false;
    FrameStats frame;
    session.render(view(90.0, 20.0), &frame);  // along x: its build waits at the gate
    EXPECT_TRUE(frame.stale);
    EXPECT_TRUE(session.building());
    session.render(view(0.0, 85.0), &frame);  // along z, before x is done
    EXPECT_TRUE(frame.stale);
    EXPECT_EQ(session.buildsCancelled(), 1);
    EXPECT_TRUE(session.building());  // z's
    volume.open = true;
    FrameStats settled;
    const Framebuffer image = session.renderSettled(view(0.0, 85.0), &settled);
    EXPECT_FALSE(settled.stale);
    EXPECT_EQ(session.stacksBuilt(), 2);  // y and z: x never finished
    EXPECT_EQ(session.buildsCancelled(), 1);
    EXPECT_EQ(image.rgba, freshFrame(scene, view(0.0, 85.0)).rgba);
}

/// gvr view's settings: axis stacks at one sample a pixel while the view moves,
/// gvr render's still once it rests.
ShearWarpSettings movingSettings() {
    ShearWarpSettings settings;
    settings.supersampling = 1.0;
    return settings;
}
const ShearWarpSettings kStill = stillSettingsFor(movingSettings(), 1.5);

/// Waits for the still of @a camera, at rest, to be ready to draw.
void waitForTheStill(const ViewSession& session, const OrthoCamera& camera) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!session.stillToDraw(camera)) {
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the still never finished";
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

TEST(ViewSession, AViewAtRestIsDrawnAgainFromTheFinerStillStack) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    ViewSession session(scene, movingSettings(), Prefetch::None, FirstImage::Settled, kStill);
    const OrthoCamera camera = cameraFor(*volume, 30.0);
    FrameStats moving;
    const Framebuffer axisFrame = session.render(camera, &moving);
    EXPECT_FALSE(moving.still);
    EXPECT_TRUE(session.stillPending());
    EXPECT_FALSE(session.stillToDraw(camera));  // not at rest yet
    session.refineAtRest(camera);
    waitForTheStill(session, camera);
    FrameStats rested;
    const Framebuffer still = session.render(camera, &rested);
    EXPECT_TRUE(rested.still);
    EXPECT_FALSE(rested.reused);
    EXPECT_FALSE(session.stillPending());
    EXPECT_FALSE(session.stillToDraw(camera));  // drawn
    EXPECT_EQ(still.rgba, ShearWarpRenderer(scene->layers, kStill).render(camera).rgba);
    EXPECT_NE(still.rgba, axisFrame.rgba);
    EXPECT_EQ(session.stacksBuilt(), 2);

    // Moving, the frames are the coarser stack's again; resting where the still
    // stack serves, it is drawn at once, built no more.
    const OrthoCamera turned = cameraFor(*volume, 35.0);
    FrameStats moved;
    EXPECT_EQ(session.render(turned, &moved).rgba,
              ShearWarpRenderer(scene->layers, movingSettings()).render(turned).rgba);
    EXPECT_FALSE(moved.still);
    EXPECT_TRUE(session.stillPending());
    session.refineAtRest(turned);
    EXPECT_TRUE(session.stillToDraw(turned));
    FrameStats again;
    EXPECT_EQ(session.render(turned, &again).rgba, ShearWarpRenderer(scene->layers, kStill).render(turned).rgba);
    EXPECT_TRUE(again.still && again.reused);
    EXPECT_EQ(session.stacksBuilt(), 2);
    EXPECT_FALSE(session.buildingStill());

    // Along another axis the still cannot serve: its memory goes, and a rest back
    // where it served needs it built again.
    FrameStats away;
    session.render(cameraFor(*volume, 120.0), &away);
    EXPECT_FALSE(away.still);
    session.render(turned);
    session.refineAtRest(turned);
    EXPECT_FALSE(session.stillToDraw(turned));
}

TEST(ViewSession, ScreenshotsShowTheStillWhenTheSessionHasOne) {
    const auto volume = blob();
    const Scene scene = sceneOf(*volume, 0.1f);
    for (const ShearWarpSettings& still : {kStill, stillSettingsFor(viewStacks(), 2.0)}) {
        ViewSession session(scene, movingSettings(), Prefetch::None, FirstImage::CoarseFirst, still);
        FrameStats settled;
        const Framebuffer image = session.renderSettled(cameraFor(*volume, 60.0), &settled);
        EXPECT_TRUE(settled.still);
        EXPECT_EQ(image.rgba, ShearWarpRenderer(scene->layers, still).render(cameraFor(*volume, 60.0)).rgba);
    }
}

TEST(ViewSession, AStillThatCannotServeTheViewIsCancelledAndNoneStartsBesideAMovingBuild) {
    GatedVolume volume(blob());
    const Scene scene = sceneOf(volume, 0.1f);
    ViewSession session(scene, movingSettings(), Prefetch::None, FirstImage::Settled, kStill);
    session.render(cameraFor(volume, 30.0));  // along y
    volume.open = false;
    session.refineAtRest(cameraFor(volume, 30.0));  // waits at the gate
    EXPECT_TRUE(session.buildingStill());
    EXPECT_FALSE(session.building());  // the still does not hold up the moving frames' builds
    FrameStats moved;
    session.render(cameraFor(volume, 40.0), &moved);  // still along y: the still's build goes on
    EXPECT_FALSE(moved.still || moved.stale);
    EXPECT_EQ(session.buildsCancelled(), 0);
    session.render(cameraFor(volume, 120.0), &moved);  // along x: its build waits at the gate
    EXPECT_TRUE(moved.stale);
    EXPECT_EQ(session.buildsCancelled(), 1);
    EXPECT_FALSE(session.buildingStill());
    // The moving frames' own build comes first: no still starts beside it.
    session.refineAtRest(cameraFor(volume, 120.0));
    EXPECT_FALSE(session.buildingStill());
    volume.open = true;
    FrameStats settled;
    const Framebuffer image = session.renderSettled(cameraFor(volume, 120.0), &settled);
    EXPECT_TRUE(settled.still);
    EXPECT_EQ(image.rgba, ShearWarpRenderer(scene->layers, kStill).render(cameraFor(volume, 120.0)).rgba);
}

TEST(ViewSession, AViewFarFromEveryStackWaitsRatherThanShearingAtGrazingAngles) {
    const auto volume = blob();
    ViewSession session(sceneOf(*volume, 0.1f), ShearWarpSettings{});
    const Framebuffer front = session.render(cameraFor(*volume, 0.0));
    FrameStats side;
    const Framebuffer repeated = session.render(cameraFor(*volume, 90.0), &side);
    EXPECT_TRUE(side.stale);
    EXPECT_EQ(repeated.rgba, front.rgba);  // the last frame again, not a shear at 90 degrees
}

}  // namespace
}  // namespace gvr
