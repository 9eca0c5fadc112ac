#include "workflow/RenderInput.h"

#include "io/GridBuilder.h"
#include "io/asset/AssetFile.h"
#include "io/formats/FileKind.h"
#include "io/formats/TransferFunctionFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "render/VolumeClassifier.h"

#include <filesystem>

namespace gvr {

namespace {

/// The bounded reconstruction of @a asset as a grid that ingest would have built
/// from it: the source's thresholds, modality and background, so that presets,
/// windows and empty space come out as they do for the source.
openvdb::GridBase::Ptr boundedGrid(const GaussianAsset& asset, const std::string& name, const ProgressFn& progress) {
    DenseVolume dense;
    {
        const FloatVolume reconstruction = boundedReconstruction(asset, name, progress);
        dense.dims = {reconstruction.dims.x(), reconstruction.dims.y(), reconstruction.dims.z()};
        dense.channels = reconstruction.channels;
        dense.type = SampleType::Float32;
        const auto* bytes = reinterpret_cast<const unsigned char*>(reconstruction.values.data());
        dense.samples.assign(bytes, bytes + reconstruction.values.size() * sizeof(float));
    }
    dense.worldFromIndex = asset.worldFromIndex;
    dense.modality = asset.source.modality;
    GridBuildSettings settings;
    settings.sourceFile = name;
    settings.threshold = asset.source.threshold;
    settings.thresholdAbove = asset.source.thresholdAbove;
    return buildGrid(dense, settings);
}

}  // namespace

std::unique_ptr<RenderVolume> assetRenderVolume(const GaussianAsset& asset, AssetLayers layers, float minScale,
                                                const std::string& name, const ProgressFn& progress) {
    // An asset is drawn from its voxels: at worst a float grid of its source's size.
    const openvdb::Vec3i& dims = asset.source.dims;
    checkVolumeFitsInMemory(name, {dims.x(), dims.y(), dims.z()}, asset.params.channels, 0, "render");
    if (readsResidualLayer(asset, layers))
        return std::make_unique<GridRenderVolume>(boundedGrid(asset, name, progress));
    return std::make_unique<GaussianRenderVolume>(asset, minScale);
}

RenderInput loadRenderInput(const std::string& path, const std::string& show, const std::string& hide,
                            AssetLayers layers, float minScale, const IngestOptions& ingest,
                            const ProgressFn& progress) {
    RenderInput input;
    if (fileKind(path) != FileKind::Asset) {
        if (!show.empty() || !hide.empty()) {
            throw InputError(path, "`show` and `hide` select the structures of a Gaussian asset fitted with `labels`");
        }
        input.volume = std::make_unique<GridRenderVolume>(loadOrIngest(path, ingest).grid);
        return input;
    }
    input.asset = selectStructures(readAsset(path), show, hide, path);
    input.volume = assetRenderVolume(*input.asset, layers, minScale, path, progress);
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
