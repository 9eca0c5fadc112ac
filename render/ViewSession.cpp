#include "ViewSession.h"

#include <algorithm>
#include <chrono>

namespace gvr {

namespace {

/// Beyond this angle from the stack's normal the shear of a stale stack runs away.
constexpr double kMaxStaleAngleDeg = 50.0;

/// A stack of samples coarser than this many image pixels (zoomed in) looks blurred;
/// one much finer (zoomed out) costs time for nothing.
constexpr double kZoomInLimit = 1.5, kZoomOutLimit = 2.0;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ViewSession::ViewSession(Scene scene, const ShearWarpSettings& settings)
    : mScene(std::move(scene)), mSettings(settings) {}

ViewSession::~ViewSession() {
    if (mBuild.valid()) mBuild.wait();
}

void ViewSession::setScene(Scene scene) { mScene = std::move(scene); }

bool ViewSession::fits(const OrthoCamera& camera) const {
    if (!mCurrent.stack || mCurrent.scene != mScene) return false;
    const StackGeometry& g = mCurrent.stack->geometry();
    // Stacks are never finer than a voxel (SliceStack), however far the view zooms in.
    const double wanted = std::max(camera.pixelMm, mCurrent.scene->layers.front().volume->voxelMm());
    const double samplesPerPixel = wanted / g.pixelMm;
    return angleBetweenDeg(camera.direction, g.normal) <= mSettings.reuseAngleDeg &&
           samplesPerPixel * kZoomInLimit >= 1.0 && samplesPerPixel <= kZoomOutLimit;
}

bool ViewSession::shearableFor(const OrthoCamera& camera) const {
    return mCurrent.stack && angleBetweenDeg(camera.direction, mCurrent.stack->geometry().normal) <= kMaxStaleAngleDeg;
}

void ViewSession::startBuild(const OrthoCamera& camera) {
    mBuild = std::async(std::launch::async, [scene = mScene, direction = camera.direction, pixelMm = camera.pixelMm,
                                             spacing = mSettings.sliceSpacingVoxels] {
        const auto start = std::chrono::steady_clock::now();
        BuiltStack built;
        built.scene = scene;
        built.stack = std::make_unique<SliceStack>(scene->layers, direction, spacing, pixelMm);
        built.buildMs = millisecondsSince(start);
        return built;
    });
}

void ViewSession::adoptFinishedBuild(FrameStats& frame) {
    if (!mBuild.valid() || mBuild.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    mCurrent = mBuild.get();
    ++mStacksBuilt;
    frame.reused = false;
    frame.buildMs = mCurrent.buildMs;
    frame.gaussiansTouched = mCurrent.stack->gaussiansTouched();
}

Framebuffer ViewSession::render(const OrthoCamera& camera, FrameStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    FrameStats frame;
    frame.index = mFrames++;
    frame.reused = true;
    adoptFinishedBuild(frame);
    if (!fits(camera) && !mBuild.valid()) startBuild(camera);
    const bool sameSize = mLastFrame.width == camera.width && mLastFrame.height == camera.height;
    // Nothing to show meanwhile (the first frame, or a new size far off): wait.
    while (!sameSize && !shearableFor(camera)) {
        if (!mBuild.valid()) startBuild(camera);
        mBuild.wait();
        adoptFinishedBuild(frame);
    }
    frame.stale = !fits(camera);
    if (!frame.stale || shearableFor(camera) || !sameSize) {
        mLastFrame = shearWarpFrame(*mCurrent.stack, camera, mSettings.terminationOpacity, frame);
    }
    frame.totalMs = millisecondsSince(start);
    if (stats) *stats = frame;
    return mLastFrame;
}

Framebuffer ViewSession::renderSettled(const OrthoCamera& camera, FrameStats* stats) {
    FrameStats frame;
    Framebuffer image = render(camera, &frame);
    while (frame.stale) {
        mBuild.wait();
        image = render(camera, &frame);
    }
    if (stats) *stats = frame;
    return image;
}

}  // namespace gvr
