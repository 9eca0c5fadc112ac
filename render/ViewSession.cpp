#include "render/ViewSession.h"

#include "pipeline/VolumeMetadata.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace gvr {

namespace {

/// Beyond this angle from the stack's normal the shear of a stale stack runs away.
constexpr double kMaxStaleAngleDeg = 50.0;

/// A stack of samples coarser than this many image pixels (zoomed in) looks blurred;
/// one much finer (zoomed out) costs time for nothing.
constexpr double kZoomInLimit = 1.5, kZoomOutLimit = 2.0;

/// A coarse stack's samples lie at least twice as far apart as the full stack's,
/// across and along the view, and further when that would hold more samples than this:
/// a build of about a tenth of a second on two cores.
constexpr double kMinCoarseness = 2.0, kCoarseSamples = 2.0e6;

/// Whether @a a and @a b show the same picture.
bool sameView(const OrthoCamera& a, const OrthoCamera& b) {
    return a.direction == b.direction && a.right == b.right && a.up == b.up && a.centre == b.centre &&
           a.pixelMm == b.pixelMm && a.width == b.width && a.height == b.height;
}

/// How many times further apart a coarse stack's samples lie than those of a full
/// stack with samples @a fullMm apart across its slices and @a spacingVoxels between them.
double coarsenessFor(const RenderVolume& volume, double fullMm, double spacingVoxels) {
    const openvdb::Vec3d spacing = axisSpacing(volume.worldFromIndex());
    const openvdb::Coord dims = volume.box().dim();
    const double cubicMm = dims.x() * spacing[0] * dims.y() * spacing[1] * dims.z() * spacing[2];
    const double fullSamples = cubicMm / (fullMm * fullMm * spacingVoxels * volume.voxelMm());
    return std::max(kMinCoarseness, std::cbrt(fullSamples / kCoarseSamples));
}

}  // namespace

ShearWarpSettings stillSettingsFor(ShearWarpSettings moving, double supersampling) {
    moving.supersampling = supersampling;
    return moving;
}

ViewSession::ViewSession(Scene scene, const ShearWarpSettings& settings, Prefetch prefetch, FirstImage firstImage,
                         std::optional<ShearWarpSettings> still)
    : mScene(std::move(scene)),
      mSettings(settings),
      mPrefetch(prefetch),
      mFirstImage(firstImage),
      mStillSettings(std::move(still)) {}

ViewSession::~ViewSession() {
    if (mBuild.result.valid()) cancel(mBuild);
    if (mStillBuild.result.valid()) cancel(mStillBuild);
    for (std::future<BuiltStack>& build : mCancelled) build.wait();
}

void ViewSession::setScene(Scene scene) { mScene = std::move(scene); }

bool ViewSession::fits(const StackTarget& target, const OrthoCamera& camera) const {
    if (target.scene != mScene) return false;
    const double wanted = mSettings.sampleMmFor(camera, *target.scene->layers.front().volume);
    const double samplesPerPixel = wanted / target.sampleMm;
    return mSettings.serves(target.normal, camera.direction) && samplesPerPixel * kZoomInLimit >= 1.0 &&
           samplesPerPixel <= kZoomOutLimit;
}

bool ViewSession::fits(const BuiltStack& built, const OrthoCamera& camera) const {
    if (!built.stack) return false;
    return fits(StackTarget{built.scene, built.stack->geometry().normal, built.sampleMm}, camera);
}

bool ViewSession::shearableFor(const OrthoCamera& camera) const {
    return mCurrent.stack && angleToStackDeg(camera.direction, mCurrent.stack->geometry().normal) <= kMaxStaleAngleDeg;
}

void ViewSession::recallKept(const OrthoCamera& camera) {
    const auto kept = std::find_if(mKept.begin(), mKept.end(), [&](const BuiltStack& b) { return fits(b, camera); });
    if (kept != mKept.end()) std::swap(*kept, mCurrent);
}

void ViewSession::dropKept(const openvdb::Vec3d& normal) {
    const auto dropped = [&](const BuiltStack& b) { return b.scene != mScene || b.stack->geometry().normal == normal; };
    mKept.erase(std::remove_if(mKept.begin(), mKept.end(), dropped), mKept.end());
}

void ViewSession::keep(BuiltStack built) {
    dropKept(built.stack->geometry().normal);
    if (built.scene == mScene) mKept.push_back(std::move(built));
}

ViewSession::BuiltStack ViewSession::buildStack(const StackTarget& target, double spacingVoxels, SegmentViews segments,
                                                const std::atomic<bool>* cancel, StackSampling sampling) {
    const auto start = std::chrono::steady_clock::now();
    BuiltStack built;
    built.scene = target.scene;
    built.sampleMm = target.sampleMm;
    built.stack = std::make_unique<SliceStack>(target.scene->layers, target.normal, spacingVoxels, target.sampleMm,
                                               ProgressFn{}, cancel, sampling, segments);
    built.buildMs = millisecondsSince(start);
    return built;
}

ViewSession::PendingBuild ViewSession::startBuilding(const StackTarget& target, const ShearWarpSettings& settings) {
    PendingBuild build;
    build.target = target;
    build.cancel = std::make_shared<std::atomic<bool>>(false);
    build.result = std::async(std::launch::async, [target, cancel = build.cancel, spacing = settings.sliceSpacingVoxels,
                                                   segments = settings.segmentViews()] {
        return buildStack(target, spacing, segments, cancel.get());
    });
    return build;
}

void ViewSession::startBuild(const OrthoCamera& camera, const openvdb::Vec3d& normal) {
    mBuild = startBuilding({mScene, normal, mSettings.sampleMmFor(camera, *mScene->layers.front().volume)}, mSettings);
}

void ViewSession::cancel(PendingBuild& build) {
    build.cancel->store(true);
    // A future of std::async waits for its thread when destroyed: kept until ready,
    // so that dropping it never holds up a frame.
    mCancelled.push_back(std::move(build.result));
    ++mBuildsCancelled;
}

bool ViewSession::finished(const PendingBuild& build) {
    return build.result.valid() && build.result.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void ViewSession::buildCoarse(const OrthoCamera& camera, const openvdb::Vec3d& normal, FrameStats& frame) {
    const RenderVolume& volume = *mScene->layers.front().volume;
    const double fullMm = mSettings.sampleMmFor(camera, volume);
    const double coarseness = coarsenessFor(volume, fullMm, mSettings.sliceSpacingVoxels);
    if (mSettings.stacks == StackOrientation::Axes && mCurrent.stack) keep(std::move(mCurrent));
    // A preview: an asset's Gaussians sampled directly, without waiting for its
    // voxels, which the full build evaluates in the background.
    mCurrent = buildStack({mScene, normal, coarseness * fullMm}, coarseness * mSettings.sliceSpacingVoxels,
                          mSettings.segmentViews(), nullptr, StackSampling::Preview);
    ++mStacksBuilt;
    frame.reused = false;
    frame.buildMs = mCurrent.buildMs;
    frame.gaussiansTouched = mCurrent.stack->gaussiansTouched();
}

void ViewSession::prefetchNextAxis(const OrthoCamera& camera) {
    if (mPrefetch != Prefetch::NextAxis || mSettings.stacks != StackOrientation::Axes || building() ||
        !fits(mCurrent, camera)) {
        return;
    }
    const openvdb::Vec3d& d = camera.direction;
    const openvdb::Vec3d nearest = mSettings.stackNormalFor(d);
    int next = -1;
    for (int a = 0; a < 3; ++a) {
        if (nearest[a] == 0.0 && (next < 0 || std::abs(d[a]) > std::abs(d[next]))) next = a;
    }
    const openvdb::Vec3d normal(next == 0, next == 1, next == 2);
    const bool held = std::any_of(mKept.begin(), mKept.end(), [&](const BuiltStack& b) {
        return b.scene == mScene && b.stack->geometry().normal == normal;
    });
    if (!held) startBuild(camera, normal);
}

void ViewSession::adoptFinishedBuild(const OrthoCamera& camera, FrameStats& frame) {
    if (!finished(mBuild)) return;
    BuiltStack built = mBuild.result.get();
    ++mStacksBuilt;
    if (!fits(built, camera) && fits(mCurrent, camera)) {
        if (mSettings.stacks == StackOrientation::Axes) keep(std::move(built));
        return;
    }
    if (mSettings.stacks == StackOrientation::Axes && mCurrent.stack) keep(std::move(mCurrent));
    mCurrent = std::move(built);
    dropKept(mCurrent.stack->geometry().normal);  // one stack an axis
    frame.reused = false;
    frame.buildMs = mCurrent.buildMs;
    frame.gaussiansTouched = mCurrent.stack->gaussiansTouched();
}

Framebuffer ViewSession::render(const OrthoCamera& camera, FrameStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    FrameStats frame;
    frame.index = mFrames++;
    frame.reused = true;
    const auto stopped = [](std::future<BuiltStack>& build) {
        return build.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    };
    mCancelled.erase(std::remove_if(mCancelled.begin(), mCancelled.end(), stopped), mCancelled.end());
    if (drawStill(camera, frame)) {
        frame.totalMs = millisecondsSince(start);
        if (stats) *stats = frame;
        return mLastFrame;
    }
    adoptFinishedBuild(camera, frame);
    if (!fits(mCurrent, camera)) recallKept(camera);
    // The view has moved on from what is being built (a prefetch included): build what it needs now.
    if (!fits(mCurrent, camera) && building() && !fits(mBuild.target, camera)) cancel(mBuild);
    const openvdb::Vec3d normal = mSettings.stackNormalFor(camera.direction);
    const bool sameSize = mLastFrame.width == camera.width && mLastFrame.height == camera.height;
    // Before the full build starts, so that the two do not share the cores.
    if (mFirstImage == FirstImage::CoarseFirst && !sameSize && !shearableFor(camera) && !building()) {
        buildCoarse(camera, normal, frame);
    }
    if (!fits(mCurrent, camera) && !building()) startBuild(camera, normal);
    // Nothing to show meanwhile (the first frame, or a new size far off): wait.
    while (!sameSize && !shearableFor(camera)) {
        if (!building()) startBuild(camera, normal);
        mBuild.result.wait();
        adoptFinishedBuild(camera, frame);
        if (!fits(mCurrent, camera)) recallKept(camera);
    }
    frame.stale = !fits(mCurrent, camera);
    if (!frame.stale || shearableFor(camera) || !sameSize) {
        mLastFrame = mFramer.frame(*mCurrent.stack, camera, mSettings, frame);
    }
    prefetchNextAxis(camera);
    frame.totalMs = millisecondsSince(start);
    if (stats) *stats = frame;
    return mLastFrame;
}

Framebuffer ViewSession::renderSettled(const OrthoCamera& camera, FrameStats* stats) {
    FrameStats frame;
    if (mStillSettings) {
        mRestingOn = camera;
        if (!holdsStillFor(camera)) {
            startStill(camera);
            mStillBuild.result.wait();
        }
    }
    Framebuffer image = render(camera, &frame);
    while (frame.stale) {
        mBuild.result.wait();
        image = render(camera, &frame);
    }
    if (stats) *stats = frame;
    return image;
}

ViewSession::StackTarget ViewSession::stillTargetFor(const OrthoCamera& camera) const {
    const RenderVolume& volume = *mScene->layers.front().volume;
    return {mScene, mStillSettings->stackNormalFor(camera.direction), mStillSettings->sampleMmFor(camera, volume)};
}

bool ViewSession::stillServes(const StackTarget& target, const OrthoCamera& camera) const {
    const StackTarget wanted = stillTargetFor(camera);
    return target.scene == wanted.scene && target.sampleMm == wanted.sampleMm &&
           mStillSettings->serves(target.normal, camera.direction);
}

bool ViewSession::holdsStillFor(const OrthoCamera& camera) const {
    return mStill.stack && stillServes(mStillTarget, camera);
}

bool ViewSession::stillToDraw(const OrthoCamera& camera) const {
    if (!stillPending() || !mRestingOn || !sameView(*mRestingOn, camera)) return false;
    return holdsStillFor(camera) || (finished(mStillBuild) && stillServes(mStillBuild.target, camera));
}

void ViewSession::startStill(const OrthoCamera& camera) {
    if (mStillBuild.result.valid() && stillServes(mStillBuild.target, camera)) return;
    if (mStillBuild.result.valid()) cancel(mStillBuild);
    mStill = BuiltStack{};
    mStillBuild = startBuilding(stillTargetFor(camera), *mStillSettings);
}

void ViewSession::refineAtRest(const OrthoCamera& camera) {
    if (!mStillSettings) return;
    mRestingOn = camera;
    // After the moving frames' own build: the two would share the cores.
    if (!holdsStillFor(camera) && !building()) startStill(camera);
}

void ViewSession::adoptFinishedStill() {
    if (!finished(mStillBuild)) return;
    mStillTarget = mStillBuild.target;
    mStill = mStillBuild.result.get();
    mStillFresh = true;
    ++mStacksBuilt;
}

bool ViewSession::drawStill(const OrthoCamera& camera, FrameStats& frame) {
    mStillShown = false;
    if (!mStillSettings) return false;
    adoptFinishedStill();
    if (mRestingOn && !sameView(*mRestingOn, camera)) mRestingOn.reset();
    if (mStillBuild.result.valid() && !stillServes(mStillBuild.target, camera)) cancel(mStillBuild);
    if (mStill.stack && !holdsStillFor(camera)) mStill = BuiltStack{};  // its memory goes
    if (!mRestingOn || !mStill.stack) return false;
    frame.still = true;
    if (mStillFresh) {
        frame.reused = false;
        frame.buildMs = mStill.buildMs;
        frame.gaussiansTouched = mStill.stack->gaussiansTouched();
        mStillFresh = false;
    }
    mLastFrame = mFramer.frame(*mStill.stack, camera, *mStillSettings, frame);
    mStillShown = true;
    return true;
}

}  // namespace gvr
