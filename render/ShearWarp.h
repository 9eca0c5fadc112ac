/// @file ShearWarp.h
/// @brief Shear-warp rendering (Lacroute and Levoy; the paper's section 3.4): one
/// stack of slices, sheared and composited front to back into an intermediate
/// image, then warped to the final image. The stack is reused while the view stays
/// within a cone around the direction it was built for, and rebuilt beyond.
#pragma once

#include "Camera.h"
#include "Framebuffer.h"
#include "SliceStack.h"

#include <memory>

namespace gvr {

struct ShearWarpSettings {
    double sliceSpacingVoxels = 1.0;   ///< slice spacing in voxels (the smallest voxel edge); > 0
    double reuseAngleDeg = 15.0;       ///< keep the stack while the view is within this; [0, 60]
    float terminationOpacity = 0.98f;  ///< a pixel stops accumulating at this opacity; (0, 1]
    /// @return an empty string, or what is wrong, naming the flag.
    std::string validate() const;
    /// How thin a Gaussian may be before GaussianRenderVolume widens it: half a slice,
    /// so that none falls between two slices.
    float minimumFootprintVoxels() const { return float(0.5 * sliceSpacingVoxels); }
};

/// What one frame cost, as `gvr render --stats` writes it.
struct FrameStats {
    int index = 0;
    bool reused = false;  ///< the stack was kept from an earlier frame
    double buildMs = 0, compositeMs = 0, warpMs = 0, totalMs = 0;
    std::size_t gaussiansTouched = 0;  ///< Gaussians evaluated to build the stack (0 when reused)
    /// Drawn from a stack built for another view or scene, or the last frame
    /// repeated, while the right stack builds in the background (ViewSession).
    bool stale = false;
};

/// Composites @a stack for @a camera's view and warps it to the image, whatever
/// the stack's direction (up to the grazing angles where the shear runs away);
/// fills in stats.compositeMs and warpMs.
Framebuffer shearWarpFrame(const SliceStack& stack, const OrthoCamera& camera, float terminationOpacity,
                           FrameStats& stats);

class ShearWarpRenderer {
public:
    ShearWarpRenderer(const RenderVolume& volume, const Classifier& classifier, const ShearWarpSettings& settings);
    /// Several layers in one stack (see SliceStack), e.g. structures with their own styles.
    ShearWarpRenderer(std::vector<StackLayer> layers, const ShearWarpSettings& settings);

    /// Renders @a camera's view; builds a stack first when there is none or the view
    /// is more than reuseAngleDeg from the stack's direction.
    Framebuffer render(const OrthoCamera& camera, FrameStats* stats = nullptr);

    const SliceStack* stack() const { return mStack.get(); }

private:
    std::vector<StackLayer> mLayers;
    ShearWarpSettings mSettings;
    std::unique_ptr<SliceStack> mStack;
    int mFrames = 0;
};

}  // namespace gvr
