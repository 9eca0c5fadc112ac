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

bool ViewSession::fits(const BuiltStack& built, const OrthoCamera& camera) const {
    if (!built.stack || built.scene != mScene) return false;
    const StackGeometry& g = built.stack->geometry();
    // Stacks are never finer than a voxel (SliceStack), however far the view zooms in.
    const double wanted = std::max(camera.pixelMm, built.scene->layers.front().volume->voxelMm());
    const double samplesPerPixel = wanted / g.pixelMm;
    return mSettings.serves(g.normal, camera.direction) && samplesPerPixel * kZoomInLimit >= 1.0 &&
           samplesPerPixel <= kZoomOutLimit;
}

bool ViewSession::shearableFor(const OrthoCamera& camera) const {
    return mCurrent.stack && angleToStackDeg(camera.direction, mCurrent.stack->geometry().normal) <= kMaxStaleAngleDeg;
}

void ViewSession::recallKept(const OrthoCamera& camera) {
    const auto kept = std::find_if(mKept.begin(), mKept.end(), [&](const BuiltStack& b) { return fits(b, camera); });
    if (kept != mKept.end()) std::swap(*kept, mCurrent);
}

void ViewSession::startBuild(const OrthoCamera& camera) {
    mBuild = std::async(std::launch::async, [scene = mScene, direction = mSettings.stackNormalFor(camera.direction),
                                             pixelMm = camera.pixelMm, spacing = mSettings.sliceSpacingVoxels] {
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
    if (mSettings.stacks == StackOrientation::axes) mKept.push_back(std::move(mCurrent));
    mCurrent = mBuild.get();
    // One stack an axis, of the scene on show: a stack replaced or of another scene goes.
    mKept.erase(std::remove_if(mKept.begin(), mKept.end(),
                               [&](const BuiltStack& b) {
                                   return !b.stack || b.scene != mScene ||
                                          b.stack->geometry().normal == mCurrent.stack->geometry().normal;
                               }),
                mKept.end());
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
    if (!fits(mCurrent, camera)) recallKept(camera);
    if (!fits(mCurrent, camera) && !mBuild.valid()) startBuild(camera);
    const bool sameSize = mLastFrame.width == camera.width && mLastFrame.height == camera.height;
    // Nothing to show meanwhile (the first frame, or a new size far off): wait.
    while (!sameSize && !shearableFor(camera)) {
        if (!mBuild.valid()) startBuild(camera);
        mBuild.wait();
        adoptFinishedBuild(frame);
    }
    frame.stale = !fits(mCurrent, camera);
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
