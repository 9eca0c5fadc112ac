/// @file ViewSession.h
/// @brief Shear-warp frames for an interactive window: when the view needs a stack
/// it does not have (or the scene changes), the new stack is built in the background
/// while frames keep coming from the old one, so the window never waits for a build.
/// A build that the view has moved away from is cancelled for the one it needs now.
/// Stacks across the axes are kept, so that an orbit builds each at most once. Once
/// the view rests, a session may draw a still instead: a finer stack, built in the
/// background and kept while it serves the view, so that the frame rate comes from
/// coarse stacks and what a person studies from fine ones.
#pragma once

#include "render/ShearWarp.h"
#include "render/StyledLayers.h"

#include <atomic>
#include <future>
#include <memory>
#include <optional>
#include <vector>

namespace gvr {

/// What a session draws: the layers and the volumes they point into.
using Scene = std::shared_ptr<const StyledLayers>;

/// What a session with axis stacks builds while it has nothing else to build.
enum class Prefetch {
    None,
    /// The stack across the axis the view is second nearest to, where a turn goes
    /// next: crossing to it then draws at once, not from a stale stack.
    NextAxis,
};

/// What a session draws when it has no stack to shear for the view (the first
/// frame, or a new size far from every stack kept).
enum class FirstImage {
    /// Waits for the stack built for the view.
    Settled,
    /// Builds a coarse stack at once, its samples at least twice as far apart as the
    /// full stack's across and along the view (further on large volumes, so that the
    /// build stays short), and draws from it (stats.stale) while the full stack
    /// builds in the background. The coarse stack is a preview (StackSampling): an
    /// asset's comes from its Gaussians at once, not from its voxels, which the
    /// full build evaluates.
    CoarseFirst,
};

/// The settings of the still drawn once the view rests: those of @a moving, with
/// @a supersampling samples a pixel side (`gvr render`'s 1.5 passes the one-ray ray
/// marcher, axis stacks included: docs/benchmarks.md).
ShearWarpSettings stillSettingsFor(ShearWarpSettings moving, double supersampling);

class ViewSession {
public:
    /// @param still  the settings of the still drawn once the view rests
    ///               (refineAtRest); none: the moving frames stay
    ViewSession(Scene scene, const ShearWarpSettings& settings, Prefetch prefetch = Prefetch::None,
                FirstImage firstImage = FirstImage::Settled, std::optional<ShearWarpSettings> still = std::nullopt);
    ~ViewSession();  ///< cancels a build in progress, and waits for it to stop

    /// Draw @a scene from the next frame on (its stack is built in the background).
    void setScene(Scene scene);

    /// A frame of @a camera's view. Waits only for the very first stack (or, with
    /// FirstImage::CoarseFirst, for a coarse one, built at once); later,
    /// frames that need another stack come from the current one (stats.stale) until
    /// the new one is ready, or repeat the last frame where the current one cannot
    /// be sheared that far.
    Framebuffer render(const OrthoCamera& camera, FrameStats* stats = nullptr);

    /// The same, from the stack built for this view and scene (the still, when the
    /// session has one): waits for builds as needed (for screenshots, which must
    /// show what `gvr render` would).
    Framebuffer renderSettled(const OrthoCamera& camera, FrameStats* stats = nullptr);

    /// The view has rested on @a camera: render() draws it from the still (stats.still)
    /// until the view moves, once a still stack that serves it is there. Starts
    /// building one in the background unless the session has no still settings,
    /// holds or builds one already, or builds a stack for the moving frames (then
    /// at a later call).
    void refineAtRest(const OrthoCamera& camera);
    /// Whether the last frame was not the still of a view at rest: a still may be to
    /// come (false when the session has no still settings).
    bool stillPending() const { return mStillSettings && !mStillShown; }
    /// Whether render() would now draw @a camera, at rest, from a still it has not drawn yet.
    bool stillToDraw(const OrthoCamera& camera) const;
    bool buildingStill() const { return mStillBuild.result.valid(); }

    bool building() const { return mBuild.result.valid(); }
    int stacksBuilt() const { return mStacksBuilt; }
    /// Builds abandoned because the view or the scene moved on before they finished.
    int buildsCancelled() const { return mBuildsCancelled; }

private:
    struct BuiltStack {
        Scene scene;
        std::unique_ptr<SliceStack> stack;
        double sampleMm = 0;  ///< asked for: the stack's lattice may keep to the voxel centres nearby
        double buildMs = 0;
    };

    /// What a stack is built for: enough to tell whether it will serve a view.
    struct StackTarget {
        Scene scene;
        openvdb::Vec3d normal;
        double sampleMm = 0;

        bool operator==(const StackTarget& other) const {
            return scene == other.scene && normal == other.normal && sampleMm == other.sampleMm;
        }
    };

    /// A stack building on another thread, and the flag that stops it.
    struct PendingBuild {
        std::future<BuiltStack> result;
        StackTarget target;                         ///< what it builds
        std::shared_ptr<std::atomic<bool>> cancel;  ///< shared with its thread
    };

    /// The scene's stack across @a normal, built now on this thread.
    static BuiltStack buildStack(const StackTarget& target, double spacingVoxels, SegmentViews segments,
                                 const std::atomic<bool>* cancel = nullptr,
                                 StackSampling sampling = StackSampling::Voxels);
    bool fits(const StackTarget& target, const OrthoCamera& camera) const;
    bool fits(const BuiltStack& built, const OrthoCamera& camera) const;
    bool shearableFor(const OrthoCamera& camera) const;
    /// Makes a kept stack that fits @a camera the current one, if there is one.
    void recallKept(const OrthoCamera& camera);
    /// Forgets the kept stacks across @a normal, and those of another scene.
    void dropKept(const openvdb::Vec3d& normal);
    /// Keeps @a built among the stacks of other axes, in place of any across the same axis.
    void keep(BuiltStack built);
    static PendingBuild startBuilding(const StackTarget& target, const ShearWarpSettings& settings);
    void startBuild(const OrthoCamera& camera, const openvdb::Vec3d& normal);
    /// Stops @a build without waiting for it: it finishes its slab alone, and is
    /// forgotten once it has.
    void cancel(PendingBuild& build);
    static bool finished(const PendingBuild& build);
    /// The still @a camera's view would be built for.
    StackTarget stillTargetFor(const OrthoCamera& camera) const;
    /// Whether a still built for @a target serves @a camera's view.
    bool stillServes(const StackTarget& target, const OrthoCamera& camera) const;
    bool holdsStillFor(const OrthoCamera& camera) const;
    /// Starts building @a camera's still, unless one that serves it is building;
    /// a held still that does not serve it goes, and its memory with it.
    void startStill(const OrthoCamera& camera);
    /// Makes a finished still build the held still.
    void adoptFinishedStill();
    /// Draws @a camera from the still when the view rests there and one serves it;
    /// drops the still, or cancels a still's build, that cannot serve the view.
    bool drawStill(const OrthoCamera& camera, FrameStats& frame);
    /// Makes a coarse stack for @a camera the current one (FirstImage::CoarseFirst).
    void buildCoarse(const OrthoCamera& camera, const openvdb::Vec3d& normal, FrameStats& frame);
    void prefetchNextAxis(const OrthoCamera& camera);
    /// Takes a finished build: as the current stack when it serves @a camera or the
    /// current one does not, else (a prefetched stack) among the kept ones.
    void adoptFinishedBuild(const OrthoCamera& camera, FrameStats& frame);

    Scene mScene;
    ShearWarpSettings mSettings;
    Prefetch mPrefetch;
    FirstImage mFirstImage;
    std::optional<ShearWarpSettings> mStillSettings;
    BuiltStack mCurrent;
    std::vector<BuiltStack> mKept;  ///< other axes' stacks, never empty ones
    PendingBuild mBuild;
    BuiltStack mStill;
    StackTarget mStillTarget;  ///< what mStill was built for
    PendingBuild mStillBuild;
    std::optional<OrthoCamera> mRestingOn;            ///< the view at rest, until it moves
    bool mStillShown = false, mStillFresh = false;    ///< the last frame was the still; mStill not drawn yet
    std::vector<std::future<BuiltStack>> mCancelled;  ///< cancelled builds still stopping
    Framebuffer mLastFrame;
    ShearWarpFramer mFramer;
    int mFrames = 0, mStacksBuilt = 0, mBuildsCancelled = 0;
};

}  // namespace gvr
