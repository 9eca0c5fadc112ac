#include "workflow/RenderInput.h"

#include "io/AssetFile.h"
#include "io/MemoryBudget.h"
#include "io/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "render/VolumeClassifier.h"

#include <filesystem>

namespace gvr {

std::unique_ptr<GaussianRenderVolume> assetRenderVolume(const GaussianAsset& asset, float minScale,
                                                        const std::string& name) {
    // An asset is drawn from its voxels: at worst a float grid of its source's size.
    const openvdb::Vec3i& dims = asset.source.dims;
    checkVolumeFitsInMemory(name, {dims.x(), dims.y(), dims.z()}, asset.params.channels, 0, "render");
    return std::make_unique<GaussianRenderVolume>(asset, minScale);
}

RenderInput loadRenderInput(const std::string& path, const std::string& show, const std::string& hide, float minScale,
                            const IngestOptions& ingest) {
    RenderInput input;
    if (!isAssetFile(path)) {
        if (!show.empty() || !hide.empty()) {
            throw InputError(path, "`show` and `hide` select the structures of a Gaussian asset fitted with `labels`");
        }
        input.volume = std::make_unique<GridRenderVolume>(loadOrIngest(path, ingest).grid);
        return input;
    }
    input.asset = selectStructures(readAsset(path), show, hide, path);
    input.volume = assetRenderVolume(*input.asset, minScale, path);
    return input;
}

TransferFunction transferFunctionFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch) {
    // Anything on disk by that name is meant as a file, so a FIFO is refused as one.
    if (!tf.empty() && std::filesystem::exists(tf)) return readTransferFunction(tf);
    return presetFor(volume, tf, mismatch);
}

Classifier classifierFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch) {
    return volumeClassifier(volume, transferFunctionFor(tf, volume, mismatch));
}

}  // namespace gvr
