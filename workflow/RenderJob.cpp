#include "workflow/RenderJob.h"

#include "pipeline/Error.h"

#include <chrono>

namespace gvr {

namespace {

StyledLayers styledLayersOf(const RenderInput& input, const Classifier& classifier, const RenderRequest& request) {
    if (request.labelStyles.empty()) return {};
    const std::string& name = request.labelStylesName;
    if (!input.asset || request.renderer != RendererKind::ShearWarp) {
        throw InputError(name, "styles the structures of a Gaussian asset fitted with `labels` (shear-warp)");
    }
    if (input.asset->labelTable.names.empty()) {
        throw InputError(name, "styles structures, and the asset has none: fit it with `labels`");
    }
    return styledLayers(*input.asset, request.labelStyles, classifier, request.minScale(), name);
}

}  // namespace

std::optional<RendererKind> rendererNamed(const std::string& name) {
    if (name == "shear-warp") return RendererKind::ShearWarp;
    if (name == "raymarch") return RendererKind::RayMarch;
    return std::nullopt;
}

std::string RenderRequest::validate() const {
    if (const std::string problem = shearWarp.validate(); !problem.empty()) return problem;
    // Below a hundredth of a voxel a ray marches for hours and looks no different.
    if (!(rayMarch.stepVoxels >= 0.01 && rayMarch.stepVoxels <= 0.5)) return "`step` must be in [0.01, 0.5] voxels";
    if (rayMarch.raysPerSide < 1 || rayMarch.raysPerSide > 16) return "`samples` must be 1 to 16 rays a side";
    if (rayMarch.raysPerSide != 1 && renderer != RendererKind::RayMarch) {
        return "`samples` applies to the ray marcher (`renderer` raymarch) only";
    }
    return "";
}

RenderJob::RenderJob(const RenderInput& input, const Classifier& classifier, const RenderRequest& request)
    : mVolume(*input.volume), mClassifier(classifier), mRequest(request) {
    if (const std::string problem = request.validate(); !problem.empty()) throw InputError("render", problem);
    mStyled = styledLayersOf(input, classifier, request);  // none for the ray marcher, which refuses them
    if (request.renderer == RendererKind::RayMarch) return;
    if (mStyled.layers.empty()) mStyled.layers.push_back({&mVolume, mClassifier});
    mShearWarp.emplace(std::move(mStyled.layers), request.shearWarp);
}

Framebuffer RenderJob::render(const OrthoCamera& camera, FrameStats& stats) {
    if (mShearWarp) return mShearWarp->render(camera, &stats);
    const auto start = std::chrono::steady_clock::now();
    RayMarchSettings settings = mRequest.rayMarch;
    settings.terminationOpacity = mRequest.shearWarp.terminationOpacity;
    Framebuffer image = rayMarch(mVolume, mClassifier, camera, settings);
    stats.index = mFrames++;
    stats.compositeMs = stats.totalMs = millisecondsSince(start);
    return image;
}

}  // namespace gvr
