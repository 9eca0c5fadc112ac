// gvr render INPUT -o frame.png: shear-warp (or ray-marched) images of an asset or grid.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/LayersOption.h"
#include "cli/ProgressBar.h"
#include "cli/RenderFlags.h"
#include "cli/SourceOptions.h"
#include "io/formats/ImageFile.h"
#include "io/formats/JsonText.h"
#include "io/formats/LabelStyleFile.h"
#include "io/formats/TransferFunctionFile.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "render/RayMarcher.h"
#include "render/ShearWarp.h"
#include "render/StyledLayers.h"
#include "workflow/FramePath.h"
#include "workflow/PhaseTimes.h"
#include "workflow/RenderInput.h"
#include "workflow/RenderJob.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

namespace gvr {

namespace {

struct RenderFlags {
    std::string input, output, size = "512x512", tf, renderer = "shear-warp", statsPath, saveTf, show, hide, labelStyle,
                               layers = "all";
    double azimuth = 30.0, elevation = 15.0, stepVoxels = 0.5;
    std::optional<double> minScale;
    int orbit = 0, samples = 1;
    bool json = false, quiet = false;
    ShearWarpSettings shearWarp;
    bool stacksAuto = true;  ///< --stacks auto (automaticStacks)
    SourceFlags source;
};

/// The renderer's part of the flags: what RenderJob draws.
RenderRequest renderRequest(const RenderFlags& flags) {
    RenderRequest request;
    const std::optional<RendererKind> renderer = rendererNamed(flags.renderer);
    if (!renderer) throw InputError("--renderer", "'" + flags.renderer + "' is neither shear-warp nor raymarch");
    request.renderer = *renderer;
    request.shearWarp = flags.shearWarp;
    request.rayMarch = {flags.stepVoxels, flags.shearWarp.terminationOpacity, flags.samples};
    if (flags.minScale) request.minScaleVoxels = float(*flags.minScale);
    return request;
}

/// The styles of --label-style, read once the request is known to be valid.
void addLabelStyles(const RenderFlags& flags, RenderRequest& request) {
    if (flags.labelStyle.empty()) return;
    request.labelStyles = readLabelStyles(flags.labelStyle);
    request.labelStylesName = flags.labelStyle;
}

nlohmann::json toJson(const FrameStats& s) {
    return {{"index", s.index},
            {"reused", s.reused},
            {"build_ms", s.buildMs},
            {"composite_ms", s.compositeMs},
            {"warp_ms", s.warpMs},
            {"total_ms", s.totalMs},
            {"gaussians_touched", s.gaussiansTouched}};
}

/// What drew the frames, so that a figure can be reproduced from its statistics alone.
nlohmann::json settingsJson(const RenderRequest& request) {
    // As given: a float's 0.98 would print as 0.9800000190734863.
    const double termination = std::round(double(request.shearWarp.terminationOpacity) * 1e6) / 1e6;
    if (request.renderer == RendererKind::RayMarch) {
        return {{"renderer", "raymarch"},
                {"samples", request.rayMarch.raysPerSide},
                {"step_voxels", request.rayMarch.stepVoxels},
                {"termination", termination}};
    }
    const ShearWarpSettings& s = request.shearWarp;
    return {{"renderer", "shear-warp"},
            {"stacks", s.stacks == StackOrientation::View ? "view" : "axes"},
            {"supersample", s.supersampling},
            {"slice_spacing_voxels", s.sliceSpacingVoxels},
            {"reuse_angle_deg", s.reuseAngleDeg},
            {"termination", termination},
            {"classify", classificationName(s.classification)}};
}

void writeStats(const std::string& path, const nlohmann::json& report) {
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary);
        out << jsonText(report, 2) << "\n";
        if (!out) throw InputError(path, "cannot write the statistics");
    });
}

/// Every file render writes (each frame of an orbit, the statistics, the saved
/// transfer function) against every file it reads and against each other.
void checkRenderOutputs(const RenderFlags& flags, int frames) {
    std::vector<std::string> taken{flags.input, flags.tf, flags.labelStyle};
    for (int f = 0; f < frames; ++f) {
        const std::string frame = framePath(flags.output, f, frames);
        checkOutputPath("-o", frame, taken);
        taken.push_back(frame);
    }
    if (!flags.statsPath.empty()) checkOutputPath("--stats", flags.statsPath, taken);
    taken.push_back(flags.statsPath);
    if (!flags.saveTf.empty()) checkOutputPath("--save-tf", flags.saveTf, taken);
}

void runRender(RenderFlags& flags) {
    // What comes before the first frame keeps a user waiting as much as the frame does.
    const auto start = std::chrono::steady_clock::now();
    PhaseTimes setup;
    RenderRequest request = renderRequest(flags);
    if (const std::string problem = request.validate(); !problem.empty()) throw InputError("gvr render", problem);
    if (flags.orbit < 0 || flags.orbit > 3600) throw InputError("--orbit", "must be between 1 and 3600 frames");
    const int frames = std::max(1, flags.orbit);
    if (flags.stacksAuto) request.shearWarp.stacks = automaticStacks(frames);
    checkRenderOutputs(flags, frames);
    const auto [width, height] = parseImageSize(flags.size);
    const RenderInput input = [&] {
        ProgressBar bar("residual layer", !flags.quiet);
        return loadRenderInput(flags.input, flags.show, flags.hide, parseAssetLayers(flags.layers, "--layers"),
                               request.minScale(), toIngestOptions(flags.source), bar.callback());
    }();
    setup.lap("read");
    const std::unique_ptr<RenderVolume>& volume = input.volume;
    std::string mismatch;
    const Classifier classifier = classifierFor(flags.tf, *volume, &mismatch);
    if (!mismatch.empty()) diagnostics() << "gvr: warning: --tf " << mismatch << "\n";
    if (!flags.saveTf.empty()) writeTransferFunction(flags.saveTf, classifier.transferFunction());
    const auto corners = worldCorners(volume->worldFromIndex(), volume->box());
    addLabelStyles(flags, request);
    RenderJob job(input, classifier, request);
    setup.lap("classify");
    double firstFrameMs = 0.0;
    nlohmann::json stats = nlohmann::json::array();
    ProgressBar bar("rendering", !flags.quiet && frames > 1);
    for (int f = 0; f < frames; ++f) {
        const View view{flags.azimuth + 360.0 * f / frames, flags.elevation};
        const OrthoCamera camera = makeCamera(view, corners, width, height);
        FrameStats frame;
        const Framebuffer image = job.render(camera, frame);
        if (f == 0) firstFrameMs = millisecondsSince(start);
        const std::string path = framePath(flags.output, f, frames);
        writeImage(path, image.width, image.height, image.rgba.data());
        stats.push_back(toJson(frame));
        stats.back()["file"] = path;
        bar.update(double(f + 1) / frames, "frame " + std::to_string(f + 1) + "/" + std::to_string(frames));
    }
    const nlohmann::json report = {{"settings", settingsJson(request)},
                                   {"setup_seconds", setup.json()},
                                   {"first_frame_ms", firstFrameMs},
                                   {"frames", stats}};
    if (!flags.statsPath.empty()) writeStats(flags.statsPath, report);
    if (flags.json) {
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    std::cout << "set up: " << setup.text() << "; first frame after " << std::fixed << std::setprecision(1)
              << firstFrameMs << " ms\n";
    for (const auto& s : stats) {
        std::cout << "wrote " << s["file"].get<std::string>() << ": " << std::fixed << std::setprecision(1)
                  << s["total_ms"].get<double>() << " ms"
                  << (request.renderer == RendererKind::RayMarch
                          ? " (ray marched)"
                          : (s["reused"].get<bool>()
                                 ? " (stack reused)"
                                 : " (stack built in " + std::to_string(int(s["build_ms"].get<double>())) + " ms)"))
                  << "\n";
    }
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto flags = std::make_shared<RenderFlags>();
    CLI::App* command =
        app.add_subcommand("render",
                           "Render a Gaussian asset or a grid with the shear-warp renderer (or the ray-marching "
                           "reference) to PNG or EXR; orthographic views around the volume's centre");
    command->add_option("input", flags->input, "Gaussian asset, .vdb grid, or any volume ingest reads")->required();
    command->add_option("-o,--output", flags->output, "Image to write: .png (8-bit) or .exr (float)")->required();
    command->add_option("--azimuth", flags->azimuth, "Degrees about the superior axis; 0 looks at the face")
        ->capture_default_str();
    command->add_option("--elevation", flags->elevation, "Degrees above the axial plane")->capture_default_str();
    command->add_option("--orbit", flags->orbit, "Render N frames of a turntable, OUT_0000.png ...");
    command->add_option("--size", flags->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
    command->add_option("--tf", flags->tf,
                        "Transfer function: ct, ct-bone, mri, rgb, or a JSON file "
                        "(default: rgb for colour, ct for HU, else mri)");
    command->add_option("--save-tf", flags->saveTf,
                        "Write the transfer function used (e.g. a preset fitted to this volume) as JSON, "
                        "for rendering other volumes with exactly the same one through --tf");
    command->add_option("--renderer", flags->renderer, "shear-warp, or raymarch (the reference)")
        ->check(CLI::IsMember({"shear-warp", "raymarch"}))
        ->capture_default_str();
    addStackFlags(*command, flags->shearWarp, &flags->stacksAuto);
    command->add_option("--slice-spacing", flags->shearWarp.sliceSpacingVoxels, "Slice spacing in voxels")
        ->capture_default_str();
    command->add_option("--termination", flags->shearWarp.terminationOpacity, "Early ray termination at this opacity")
        ->capture_default_str();
    command->add_option("--step", flags->stepVoxels, "Ray-march step in voxels (at most 0.5)")->capture_default_str();
    command
        ->add_option("--samples", flags->samples,
                     "Ray marcher: N x N rays per pixel, averaged; 4 is the anti-aliased reference that render "
                     "quality is measured against")
        ->check(CLI::Range(1, kMaxRaysPerSide))
        ->capture_default_str();
    command->add_option(
        "--min-scale", flags->minScale,
        "Widen Gaussians thinner than this many voxels, keeping their mass, so that they "
        "cannot fall between the voxels an asset is drawn from (default: half the slice spacing; 0: off)");
    command->add_option(
        "--stats", flags->statsPath,
        "Write the timings as JSON: the set-up (reading, transfer function), the first frame, each frame");
    command->add_option("--show", flags->show,
                        "Render only these structures of an asset fitted with --labels: IDs or names, comma-separated");
    command->add_option("--hide", flags->hide, "Leave these structures out (after --show)");
    addLayersOption(*command, flags->layers, "at its voxels; --show and --hide draw the Gaussians alone");
    command->add_option("--label-style", flags->labelStyle,
                        "Per-structure colour and opacity: JSON {\"NAME or ID\": {\"color\": [r, g, b], "
                        "\"opacity\": factor}, ...}; colours for grey assets");
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json, "Print the timings as JSON, as --stats writes them");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bar");
    command->callback([flags] { runRender(*flags); });
}

}  // namespace gvr
