#include "RenderInput.h"

#include "AssetExport.h"
#include "AssetFile.h"
#include "Camera.h"
#include "Error.h"
#include "TransferFunctionFile.h"
#include "VolumeClassifier.h"

#include <filesystem>
#include <limits>
#include <sstream>

namespace gvr {

RenderInput loadRenderInput(const std::string& path, const std::string& show, const std::string& hide, float minScale,
                            const IngestOptions& ingest, bool assetAsGrid) {
    RenderInput input;
    if (!isAssetFile(path)) {
        if (!show.empty() || !hide.empty()) {
            throw InputError(path, "--show and --hide select the structures of a Gaussian asset fitted with --labels");
        }
        input.volume = std::make_unique<GridRenderVolume>(loadOrIngest(path, ingest).grid);
        return input;
    }
    input.asset = selectStructures(readAsset(path), show, hide, path);
    if (assetAsGrid) {
        ExportSettings everything;
        everything.threshold = -std::numeric_limits<double>::infinity();
        input.volume = std::make_unique<GridRenderVolume>(exportAsset(*input.asset, everything).grids.front());
    } else {
        input.volume = std::make_unique<GaussianRenderVolume>(*input.asset, minScale);
    }
    return input;
}

std::pair<int, int> parseImageSize(const std::string& text) {
    int width = 0, height = 0;
    char x = 0;
    std::istringstream in(text);
    if (!(in >> width >> x >> height) || x != 'x' || !(in >> std::ws).eof() || width < 1 || height < 1 ||
        width > kMaxImageSide || height > kMaxImageSide) {
        throw InputError("--size", "'" + text + "' is not WIDTHxHEIGHT of 1 to " + std::to_string(kMaxImageSide) +
                                       " pixels each, e.g. 512x512");
    }
    return {width, height};
}

TransferFunction transferFunctionFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch) {
    // Anything on disk by that name is meant as a file, so a FIFO is refused as one.
    if (!tf.empty() && std::filesystem::exists(tf)) return readTransferFunction(tf);
    return presetFor(volume, tf, mismatch);
}

Classifier classifierFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch) {
    return volumeClassifier(volume, transferFunctionFor(tf, volume, mismatch));
}

void addStackFlags(CLI::App& command, ShearWarpSettings& settings) {
    // By name only: an enum option would also take its numbers, "--stacks 1" for view.
    command.add_option_function<std::string>(
               "--stacks",
               [&settings](const std::string& name) {
                   settings.stacks = name == "view" ? StackOrientation::view : StackOrientation::axes;
               },
               "axes: slice stacks across the world axis nearest the view, each built once and kept "
               "(an orbit builds two or three); view: a stack across the view, rebuilt beyond --reuse-angle")
        ->check(CLI::IsMember({"axes", "view"}))
        ->type_name("axes|view")
        ->default_str("axes");
    command.add_option("--reuse-angle", settings.reuseAngleDeg,
                       "With --stacks view: reuse the stack while the view is within this many degrees")
        ->capture_default_str();
}

}  // namespace gvr
