// gvr view INPUT: an interactive window over the shear-warp renderer. Stacks are
// rebuilt in the background (ViewSession), so dragging never waits for one.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/LayersOption.h"
#include "cli/RenderFlags.h"
#include "cli/SdlWindow.h"
#include "cli/SourceOptions.h"
#include "io/formats/ImageFile.h"
#include "io/formats/JsonText.h"
#include "pipeline/Error.h"
#include "pipeline/LabelStyle.h"
#include "render/TransferPresets.h"
#include "render/ViewSession.h"
#include "workflow/PhaseTimes.h"
#include "workflow/RenderInput.h"

#include <SDL.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

namespace gvr {

namespace {

constexpr double kDegreesPerPixel = 0.4;  ///< orbit speed of a drag
constexpr double kZoomPerNotch = 1.1;     ///< of the mouse wheel
/// A view unchanged this long is at rest: its still builds (ViewSession::refineAtRest).
constexpr double kRestSeconds = 0.2;
/// How often a window with a still to come looks for it, and one with nothing to
/// come for events, when no event arrives.
constexpr int kStillPollMs = 20, kIdleWaitMs = 250;
const std::vector<std::string> kPresets = {"ct", "ct-bone", "mri", "rgb"};

struct ViewFlags {
    std::string input, tf, show, hide, layers = "all", size = "800x800", screenshots = ".";
    double azimuth = 30.0, elevation = 15.0;
    double stillSupersampling = ShearWarpSettings{}.supersampling;  ///< 0: no still
    std::uint64_t frames = 0;
    bool json = false;
    ShearWarpSettings shearWarp;
    SourceFlags source;
};

/// What the keys and the mouse change.
struct ViewState {
    View view;
    double zoom = 1.0;
    std::string tf;  ///< a preset or the --tf file
    double opacity = 1.0;
    std::set<int> hidden;  ///< structure ids
    bool hud = true;
};

/// The interactive part: input, its scene for the current state, and the frames.
class Viewer {
public:
    Viewer(const ViewFlags& flags, RenderInput input)
        : mFlags(flags),
          mInput(std::move(input)),
          mCorners(worldCorners(mInput.volume->worldFromIndex(), mInput.volume->box())) {
        mState.view = {flags.azimuth, flags.elevation};
        mState.tf = flags.tf.empty() ? defaultPreset(mInput.volume->channels(), mInput.volume->statistics()) : flags.tf;
        mInitial = mState;
        classify();
        mSession = std::make_unique<ViewSession>(scene(), flags.shearWarp, Prefetch::NextAxis, FirstImage::CoarseFirst,
                                                 stillSettings(flags));
    }

    /// Why the transfer function does not suit the data; empty when it does.
    const std::string& mismatch() const { return mMismatch; }

    /// @param commandStart  when the command began, for the time to the first image
    void run(SdlWindow& window, std::chrono::steady_clock::time_point commandStart) {
        const auto start = std::chrono::steady_clock::now();
        bool busy = true;
        while (!mQuit) {
            // When the picture cannot change by itself, sleep in the event queue.
            const bool changed = handleEvents(busy ? 0 : mSession->stillPending() ? kStillPollMs : kIdleWaitMs);
            std::tie(mWidth, mHeight) = window.size();
            const OrthoCamera view = camera(mWidth, mHeight);
            noteMove();
            if (millisecondsSince(mLastMove) >= 1000.0 * kRestSeconds) mSession->refineAtRest(view);
            if (!changed && !busy && !mSession->stillToDraw(view)) continue;
            FrameStats frame;
            const Framebuffer image = mSession->render(view, &frame);
            recordFrame(frame);
            window.show(image, mState.hud ? hud(frame) : std::vector<std::string>{});
            if (mFrames == 1) mFirstImageMs = millisecondsSince(commandStart);
            if (!frame.stale && mRefinedImageMs == 0) mRefinedImageMs = millisecondsSince(commandStart);
            if (frame.still && mStillImageMs == 0) mStillImageMs = millisecondsSince(commandStart);
            if (mFlags.frames > 0 && mFrames >= mFlags.frames) break;
            busy = frame.stale || mSession->building() || mFlags.frames > 0;
        }
        mSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

    nlohmann::json summary() const {
        return {{"frames", mFrames},
                {"first_image_ms", mFirstImageMs},
                {"refined_image_ms", mRefinedImageMs},
                {"still_image_ms", mStillImageMs},
                {"seconds", mSeconds},
                {"mean_fps", mSeconds > 0 ? mFrames / mSeconds : 0.0},
                {"stacks_built", mSession->stacksBuilt()},
                {"builds_cancelled", mSession->buildsCancelled()},
                {"stale_frames", mStaleFrames},
                {"screenshots", mScreenshots},
                {"view",
                 {{"azimuth", mState.view.azimuthDeg}, {"elevation", mState.view.elevationDeg}, {"zoom", mState.zoom}}},
                {"tf", mState.tf},
                {"opacity_scale", mState.opacity}};
    }

private:
    /// The settings of the still a rested view gets, if any: none when they are the
    /// moving frames' own, whose stacks it would build again.
    static std::optional<ShearWarpSettings> stillSettings(const ViewFlags& flags) {
        if (flags.stillSupersampling == 0.0 || flags.stillSupersampling == flags.shearWarp.supersampling) {
            return std::nullopt;
        }
        return stillSettingsFor(flags.shearWarp, flags.stillSupersampling);
    }

    /// Restarts the wait for rest when the camera or the window has changed since the last look.
    void noteMove() {
        const auto looks =
            std::make_tuple(mState.view.azimuthDeg, mState.view.elevationDeg, mState.zoom, mWidth, mHeight);
        if (looks == mLastLooks) return;
        mLastLooks = looks;
        mLastMove = std::chrono::steady_clock::now();
    }

    OrthoCamera camera(int width, int height) const {
        OrthoCamera camera = makeCamera(mState.view, mCorners, width, height);
        camera.pixelMm /= mState.zoom;
        return camera;
    }

    /// The layers for the current state: the shown structures, the transfer
    /// function with its opacity scaled.
    Scene scene() const {
        auto scene = std::make_shared<StyledLayers>();
        const RenderVolume* volume = mInput.volume.get();
        if (!mState.hidden.empty()) {
            std::string hide;
            for (int id : mState.hidden) hide += (hide.empty() ? "" : ",") + std::to_string(id);
            const GaussianAsset shown = selectStructures(*mInput.asset, "", hide, mFlags.input);
            scene->volumes.push_back(
                std::make_unique<GaussianRenderVolume>(shown, mFlags.shearWarp.minimumFootprintVoxels()));
            volume = scene->volumes.back().get();
        }
        LabelStyle scaled;
        scaled.opacity = float(mState.opacity);
        scene->layers.push_back({volume, Classifier(styledTransferFunction(mBase->transferFunction(), scaled),
                                                    mBase->channels(), mBase->colourScale())});
        return scene;
    }

    /// The transfer function's classifier, fitted to the whole input once per
    /// choice: opacity and structure changes reuse it.
    void classify() { mBase = classifierFor(mState.tf, *mInput.volume, &mMismatch); }

    void changeScene() {
        mSession->setScene(scene());
        mLastMove = std::chrono::steady_clock::now();
    }

    /// Polls events (or waits up to @a waitMs for the first); whether any came.
    bool handleEvents(int waitMs) {
        SDL_Event event;
        bool changed = false;
        const auto next = [&] {
            return waitMs == 0 || changed ? SDL_PollEvent(&event) : SDL_WaitEventTimeout(&event, waitMs);
        };
        while (next()) {
            changed = true;
            if (event.type == SDL_QUIT) mQuit = true;
            if (event.type == SDL_MOUSEMOTION && (event.motion.state & SDL_BUTTON_LMASK)) {
                mState.view.azimuthDeg += event.motion.xrel * kDegreesPerPixel;
                mState.view.elevationDeg =
                    std::clamp(mState.view.elevationDeg + event.motion.yrel * kDegreesPerPixel, -89.0, 89.0);
            }
            if (event.type == SDL_MOUSEWHEEL) mState.zoom *= std::pow(kZoomPerNotch, event.wheel.y);
            if (event.type == SDL_KEYDOWN) handleKey(event.key.keysym.sym);
        }
        return changed;
    }

    void handleKey(SDL_Keycode key) {
        switch (key) {
            case SDLK_q:
            case SDLK_ESCAPE:
                mQuit = true;
                break;
            case SDLK_r:
                mState.view = mInitial.view;
                mState.zoom = mInitial.zoom;
                break;
            case SDLK_h:
                mState.hud = !mState.hud;
                break;
            case SDLK_s:
                screenshot();
                break;
            case SDLK_t:
                nextPreset();
                break;
            case SDLK_RIGHTBRACKET:
                mState.opacity *= 1.25;
                changeScene();
                break;
            case SDLK_LEFTBRACKET:
                mState.opacity /= 1.25;
                changeScene();
                break;
            case SDLK_0:
                mState.hidden.clear();
                changeScene();
                break;
            default:
                if (key >= SDLK_1 && key <= SDLK_9) toggleStructure(int(key - SDLK_1));
        }
    }

    /// The next preset that can classify these data (rgb colour, the others grey).
    void nextPreset() {
        const auto at = std::find(kPresets.begin(), kPresets.end(), mState.tf);
        std::size_t index = at == kPresets.end() ? 0 : std::size_t(at - kPresets.begin()) + 1;
        while (!presetTakes(kPresets[index % kPresets.size()], mInput.volume->channels())) ++index;
        mState.tf = kPresets[index % kPresets.size()];
        classify();
        changeScene();
    }

    std::vector<std::pair<int, std::string>> structures() const {
        if (!mInput.asset) return {};
        return {mInput.asset->labelTable.names.begin(), mInput.asset->labelTable.names.end()};
    }

    void toggleStructure(int index) {
        const auto list = structures();
        if (index >= int(list.size())) return;
        const int id = list[index].first;
        if (!mState.hidden.erase(id)) mState.hidden.insert(id);
        if (mState.hidden.size() == list.size()) mState.hidden.erase(id);  // keep one structure shown
        changeScene();
    }

    /// The view as `gvr render` would draw it (the stack built for it), as a PNG.
    void screenshot() {
        std::filesystem::create_directories(mFlags.screenshots);
        std::string path;
        for (int n = int(mScreenshots.size()) + 1;; ++n) {
            std::ostringstream name;
            name << mFlags.screenshots << "/gvr-view-" << std::setw(4) << std::setfill('0') << n << ".png";
            path = name.str();
            if (!std::filesystem::exists(path)) break;
        }
        const Framebuffer image = mSession->renderSettled(camera(mWidth, mHeight));
        writeImage(path, image.width, image.height, image.rgba.data());
        mScreenshots.push_back(path);
        if (!mFlags.json) std::cout << "saved " << path << std::endl;
    }

    void recordFrame(const FrameStats& frame) {
        ++mFrames;
        mStaleFrames += frame.stale;
        if (!frame.reused) mLastBuild = frame;
        // Frame time smoothed over about ten frames, so that the HUD can be read.
        mSmoothedMs = mSmoothedMs == 0 ? frame.totalMs : 0.9 * mSmoothedMs + 0.1 * frame.totalMs;
    }

    std::vector<std::string> hud(const FrameStats& frame) const {
        std::ostringstream rate, stack, view;
        rate << std::fixed << std::setprecision(1) << 1000.0 / std::max(mSmoothedMs, 1e-3) << " FPS, "
             << std::setprecision(1) << mSmoothedMs << " ms a frame";
        stack << (frame.still    ? "stack: the still"
                  : frame.stale  ? "stack: building for this view..."
                  : frame.reused ? "stack: reused"
                                 : "stack: rebuilt")
              << (mSession->buildingStill() && !frame.still ? " (the still builds)" : "") << "; last build "
              << std::fixed << std::setprecision(0) << mLastBuild.buildMs << " ms, " << mLastBuild.gaussiansTouched
              << " Gaussians touched";
        view << std::fixed << "tf " << mState.tf << " (t), opacity x" << std::setprecision(2) << mState.opacity
             << " ([ ]), azimuth " << std::setprecision(0) << mState.view.azimuthDeg << ", elevation "
             << mState.view.elevationDeg << ", zoom x" << std::setprecision(2) << mState.zoom;
        std::vector<std::string> lines = {rate.str(), stack.str(), view.str()};
        if (!mMismatch.empty()) lines.push_back("warning: " + mMismatch);
        const auto list = structures();
        for (std::size_t n = 0; n < list.size() && n < 9; ++n) {
            lines.push_back(std::to_string(n + 1) + ": " + list[n].second +
                            (mState.hidden.count(list[n].first) ? " (hidden)" : ""));
        }
        lines.push_back("drag: orbit, wheel: zoom, r: reset, s: screenshot, h: HUD, q: quit" +
                        std::string(list.empty() ? "" : ", 1-9: structures, 0: all"));
        return lines;
    }

    const ViewFlags& mFlags;
    RenderInput mInput;
    std::array<openvdb::Vec3d, 8> mCorners;
    ViewState mState, mInitial;
    std::unique_ptr<ViewSession> mSession;
    std::optional<Classifier> mBase;
    std::string mMismatch;
    bool mQuit = false;
    int mWidth = 0, mHeight = 0;
    std::uint64_t mFrames = 0, mStaleFrames = 0;
    double mSeconds = 0, mSmoothedMs = 0, mFirstImageMs = 0, mRefinedImageMs = 0, mStillImageMs = 0;
    std::tuple<double, double, double, int, int> mLastLooks;
    std::chrono::steady_clock::time_point mLastMove = std::chrono::steady_clock::now();
    FrameStats mLastBuild;
    std::vector<std::string> mScreenshots;
};

void runView(const ViewFlags& flags) {
    const auto start = std::chrono::steady_clock::now();
    PhaseTimes setup;
    const std::string problem = flags.shearWarp.validate();
    if (!problem.empty()) throw InputError("gvr view", problem);
    if (flags.stillSupersampling != 0.0 &&
        !stillSettingsFor(flags.shearWarp, flags.stillSupersampling).validate().empty()) {
        throw InputError("gvr view", "--still-supersample must be 0 (no still) or from 1 to 4");
    }
    const auto [width, height] = parseImageSize(flags.size);
    if (flags.input.empty() || !std::filesystem::exists(flags.input))
        throw InputError(flags.input, "no such file or folder");
    RenderInput input = loadRenderInput(flags.input, flags.show, flags.hide, parseAssetLayers(flags.layers, "--layers"),
                                        flags.shearWarp.minimumFootprintVoxels(), toIngestOptions(flags.source));
    setup.lap("read");
    Viewer viewer(flags, std::move(input));  // a bad --tf fails before a window opens
    setup.lap("classify");
    if (!viewer.mismatch().empty()) diagnostics() << "gvr: warning: --tf " << viewer.mismatch() << "\n";
    SdlWindow window("gvr view - " + std::filesystem::path(flags.input).filename().string(), width, height);
    setup.lap("window");
    viewer.run(window, start);
    if (!flags.json) return;
    nlohmann::json summary = viewer.summary();
    summary["setup_seconds"] = setup.json();
    std::cout << jsonText(summary, 2) << "\n";
}

}  // namespace

void addViewCommand(CLI::App& app) {
    auto flags = std::make_shared<ViewFlags>();
    CLI::App* command = app.add_subcommand(
        "view",
        "Open a window on a Gaussian asset, a .vdb grid or any volume ingest reads, drawn by the shear-warp "
        "renderer on the CPU. Drag to orbit, wheel to zoom, r resets, t cycles the presets, [ and ] scale the "
        "opacity, 1-9 show or hide structures, 0 shows all, s saves a screenshot PNG, h hides the HUD, q quits");
    command->add_option("input", flags->input, "Gaussian asset, .vdb grid, or any volume ingest reads")->required();
    command->add_option("--tf", flags->tf,
                        "Transfer function: ct, ct-bone, mri, rgb, or a JSON file "
                        "(default: rgb for colour, ct for HU, else mri)");
    command->add_option("--show", flags->show, "Only these structures of an asset fitted with --labels");
    command->add_option("--hide", flags->hide, "Leave these structures out (after --show)");
    addLayersOption(*command, flags->layers, "at its voxels; hidden structures leave the Gaussians alone");
    command->add_option("--size", flags->size, "Window size WIDTHxHEIGHT in pixels")->capture_default_str();
    command->add_option("--azimuth", flags->azimuth, "Starting azimuth in degrees, as gvr render's")
        ->capture_default_str();
    command->add_option("--elevation", flags->elevation, "Starting elevation in degrees")->capture_default_str();
    // The frame rate first: a window redraws as the mouse moves, and a still from
    // gvr render is where fidelity pays.
    flags->shearWarp.supersampling = 1.0;
    addStackFlags(*command, flags->shearWarp);
    command
        ->add_option("--still-supersample", flags->stillSupersampling,
                     "Once the view rests (0.2 s), draw it again from a stack with this many samples along each side "
                     "of a pixel, built in the background and kept while it serves the view (gvr render's default: "
                     "past the one-ray ray marcher); screenshots show it. 0 (or --supersample's value): keep the "
                     "moving frames")
        ->capture_default_str();
    command->add_option("--screenshots", flags->screenshots, "Folder for the screenshots (key s)")
        ->capture_default_str();
    command->add_option("--frames", flags->frames, "Close after this many frames (0: when the window closes)");
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json,
                      "On closing, print the set-up's, the first image's, the refined image's and the still's times, "
                      "frames, rates, rebuilds and screenshots as JSON");
    command->callback([flags] { runView(*flags); });
}

}  // namespace gvr
