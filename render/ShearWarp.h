/// @file ShearWarp.h
/// @brief Shear-warp rendering (Lacroute and Levoy; the paper's section 3.4): a
/// stack of slices, sheared and composited front to back into an intermediate
/// image, then warped to the final image. Stacks lie across the world's axes and
/// are kept, so three serve every view; or they lie across the view and are reused
/// while it stays within a cone, and rebuilt beyond.
#pragma once

#include "render/Camera.h"
#include "render/Framebuffer.h"
#include "render/SliceStack.h"

#include <algorithm>
#include <chrono>
#include <memory>

namespace gvr {

/// Which way slice stacks lie.
enum class StackOrientation {
    /// Across the world axis nearest the view, as Lacroute and Levoy's: the view is
    /// at most 54.7 degrees off it, and the three stacks, each built once, serve every view.
    Axes,
    /// Across the view itself, rebuilt when the view turns beyond reuseAngleDeg.
    View,
};

/// How a grey stack's codes are composited.
enum class CompositeLanes {
    Best,  ///< eight pixels at a time where the processor has AVX2, else one
    One,   ///< one pixel at a time on any processor: what Best does without AVX2, for tests against it
};

struct ShearWarpSettings {
    StackOrientation stacks = StackOrientation::Axes;
    double sliceSpacingVoxels = 1.0;   ///< slice spacing in voxels (the smallest voxel edge); > 0
    double reuseAngleDeg = 15.0;       ///< view stacks: keep one while the view is within this; [0, 60]
    float terminationOpacity = 0.98f;  ///< a pixel stops accumulating at this opacity; (0, 1]
    /// Stack samples along each side of an image pixel (of a voxel, when pixels are
    /// smaller); [1, 4]. The warp averages over each pixel, so that finer samples
    /// anti-alias the image: at 1 the resampling blurs and aliases by turns across
    /// the image (docs/benchmarks.md, "Supersampled stacks and a footprint warp").
    /// Along a volume's axes, as axis stacks lie, a stack of values keeps to the voxel
    /// centres nearby instead (SliceStack; docs/benchmarks.md, "Samples on the voxel centres").
    double supersampling = 1.5;
    /// How a grey volume's values are composited: segments see bands of the
    /// transfer function thinner than a slice spacing (SliceStack, Classification).
    Classification classification = Classification::Points;
    CompositeLanes compositeLanes = CompositeLanes::Best;
    /// @return an empty string, or what is wrong, naming the flag.
    std::string validate() const;
    /// How thin a Gaussian may be before GaussianRenderVolume widens it, unless
    /// `--min-scale` says otherwise: half a slice spacing.
    float minimumFootprintVoxels() const { return float(0.5 * sliceSpacingVoxels); }
    /// The spacing to ask of a stack's samples across the slices, for @a camera's pixels over
    /// @a volume's voxels: samples much finer than the voxels would only resample the
    /// same trilinear field, however far the view zooms in. (Where the view shrinks
    /// the volume, the stack takes no coarser than the voxels: SliceStack.)
    double sampleMmFor(const OrthoCamera& camera, const RenderVolume& volume) const {
        return std::max(camera.pixelMm, volume.voxelMm()) / supersampling;
    }

    /// The views a stack of these settings serves: up to the reuse angle for view
    /// stacks, and the 54.7 degrees between an axis and a cube's diagonal for axis stacks.
    SegmentViews segmentViews() const;

    /// The normal of the stack to build for a view along @a direction.
    openvdb::Vec3d stackNormalFor(const openvdb::Vec3d& direction) const;
    /// Whether a stack with @a normal serves a view along @a direction.
    bool serves(const openvdb::Vec3d& normal, const openvdb::Vec3d& direction) const;
};

/// The stacks that serve @a frames images best: a still gets a stack across its own
/// view, which needs no shear there and is the most faithful (docs/benchmarks.md,
/// "Supersampled stacks"); an orbit gets axis stacks, built once and kept.
inline StackOrientation automaticStacks(int frames) {
    return frames == 1 ? StackOrientation::View : StackOrientation::Axes;
}

/// Degrees between a view along @a direction and the slices' normal @a normal,
/// whichever side the view comes from: a stack is composited either way.
double angleToStackDeg(const openvdb::Vec3d& direction, const openvdb::Vec3d& normal);

/// What one frame cost, as `gvr render --stats` writes it.
struct FrameStats {
    int index = 0;
    bool reused = false;  ///< the stack was kept from an earlier frame
    double buildMs = 0, compositeMs = 0, warpMs = 0, totalMs = 0;
    /// Gaussians evaluated to build the stack: for an asset, all of them on the build
    /// that evaluated its voxels, 0 on every other (and for grids).
    std::size_t gaussiansTouched = 0;
    /// Drawn from a stack built for another view or scene, or the last frame
    /// repeated, while the right stack builds in the background (ViewSession).
    bool stale = false;
    /// Drawn from the still of a view at rest (ViewSession::refineAtRest).
    bool still = false;
};

/// The milliseconds of FrameStats: wall time since @a start.
inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Composites stacks and warps them to images, keeping its intermediate image's
/// memory from one frame to the next: a fresh one a frame costs its page faults,
/// and on some machines as much time again as the warp.
class ShearWarpFramer {
public:
    /// Composites @a stack for @a camera's view and warps it to the image, whatever
    /// the stack's direction (up to the grazing angles where the shear runs away);
    /// fills in stats.compositeMs and warpMs.
    Framebuffer frame(const SliceStack& stack, const OrthoCamera& camera, const ShearWarpSettings& settings,
                      FrameStats& stats);

private:
    std::vector<float> mIntermediate;
};

class ShearWarpRenderer {
public:
    ShearWarpRenderer(const RenderVolume& volume, const Classifier& classifier, const ShearWarpSettings& settings);
    /// Several layers in one stack (see SliceStack), e.g. structures with their own styles.
    ShearWarpRenderer(std::vector<StackLayer> layers, const ShearWarpSettings& settings);

    /// Renders @a camera's view; builds a stack first when none kept serves it.
    Framebuffer render(const OrthoCamera& camera, FrameStats* stats = nullptr);

    /// The stacks kept: up to three across the axes, or the last one across a view.
    const std::vector<std::unique_ptr<SliceStack>>& stacks() const { return mStacks; }

private:
    std::vector<StackLayer> mLayers;
    ShearWarpSettings mSettings;
    std::vector<std::unique_ptr<SliceStack>> mStacks;
    ShearWarpFramer mFramer;
    int mFrames = 0;
};

}  // namespace gvr
