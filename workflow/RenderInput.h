/// @file RenderInput.h
/// @brief What `gvr render`, `gvr view` and Python's render draw: a Gaussian asset (the structures
/// shown, or its residual layer's bounded reconstruction) or a grid, and the transfer function
/// given by preset or file.
#pragma once

#include "io/Ingest.h"
#include "io/asset/AssetExport.h"
#include "pipeline/GaussianAsset.h"
#include "render/Classifier.h"
#include "render/RenderVolume.h"
#include "render/ShearWarp.h"

#include <memory>
#include <optional>
#include <string>

namespace gvr {

struct RenderInput {
    std::optional<GaussianAsset> asset;    ///< the shown structures, when the input is an asset
    std::unique_ptr<RenderVolume> volume;  ///< the asset's field, or the grid
};

/// The render volume of @a layers of @a asset (named @a name in errors): its
/// Gaussians' field, or with a residual layer its bounded reconstruction, cut as
/// ingest cut the source, so that it is drawn as the source itself would be.
/// @param minScale  as for GaussianRenderVolume
/// @throw InputError when the voxels it is drawn from (at worst a float grid of its
///        source's size) would not fit in memory, or as boundedReconstruction.
std::unique_ptr<RenderVolume> assetRenderVolume(const GaussianAsset& asset, AssetLayers layers, float minScale,
                                                const std::string& name, const ProgressFn& progress = {});

/// Reads @a path: an asset (with only the structures that @a show names, less
/// @a hide: their Gaussians, without the residual layer that corrects them all) or
/// anything loadOrIngest reads.
/// @param minScale  as for GaussianRenderVolume
/// @throw InputError naming the file, also when @a show or @a hide is given for a grid.
RenderInput loadRenderInput(const std::string& path, const std::string& show, const std::string& hide,
                            AssetLayers layers, float minScale, const IngestOptions& ingest,
                            const ProgressFn& progress = {});

/// The transfer function @a tf names: a JSON file, else a preset fitted to @a volume
/// (empty: the preset for data like these). @a mismatch: as for presetFor.
TransferFunction transferFunctionFor(const std::string& tf, const RenderVolume& volume,
                                     std::string* mismatch = nullptr);

/// volumeClassifier() of transferFunctionFor().
Classifier classifierFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch = nullptr);

}  // namespace gvr
