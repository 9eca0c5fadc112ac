/// @file RenderJob.h
/// @brief What `gvr render` and Python's render share once the input is read: the
/// renderer (shear-warp, or the ray-marching reference), the structures' styles,
/// and frame after frame drawn with what the frames share kept.
#pragma once

#include "pipeline/LabelStyle.h"
#include "render/Camera.h"
#include "render/Classifier.h"
#include "render/Framebuffer.h"
#include "render/RayMarcher.h"
#include "render/ShearWarp.h"
#include "render/StyledLayers.h"
#include "workflow/RenderInput.h"

#include <map>
#include <optional>
#include <string>

namespace gvr {

enum class RendererKind { ShearWarp, RayMarch };

/// "shear-warp" or "raymarch"; nothing for any other name.
std::optional<RendererKind> rendererNamed(const std::string& name);

struct RenderRequest {
    RendererKind renderer = RendererKind::ShearWarp;
    ShearWarpSettings shearWarp;
    RayMarchSettings rayMarch;
    /// By structure name or id, as LabelStyleFile.h reads them; empty: no styles.
    std::map<std::string, LabelStyle> labelStyles;
    std::string labelStylesName;  ///< names the styles in errors (their file)
    /// Widen thinner Gaussians (see GaussianRenderVolume); nothing: half the slice spacing.
    std::optional<float> minScaleVoxels;

    float minScale() const { return minScaleVoxels.value_or(shearWarp.minimumFootprintVoxels()); }
    /// A problem with the settings, in the library's terms (`step`), or "".
    std::string validate() const;
};

/// Draws views of one input, read by loadRenderInput() with request.minScale(),
/// which must outlive the job.
class RenderJob {
public:
    /// @throw InputError when the request is invalid, or styles structures of
    ///        anything but a labelled asset drawn by shear-warp.
    RenderJob(const RenderInput& input, const Classifier& classifier, const RenderRequest& request);

    /// @a camera's view; @a stats gets its timings.
    Framebuffer render(const OrthoCamera& camera, FrameStats& stats);

private:
    const RenderVolume& mVolume;
    Classifier mClassifier;
    RenderRequest mRequest;
    StyledLayers mStyled;  ///< keeps the styled structures' volumes alive for mShearWarp
    std::optional<ShearWarpRenderer> mShearWarp;
    int mFrames = 0;  ///< drawn by the ray marcher
};

}  // namespace gvr
