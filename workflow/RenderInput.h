/// @file RenderInput.h
/// @brief What `gvr render`, `gvr view` and Python's render draw: a Gaussian asset (the structures
/// shown) or a grid, and the transfer function given by preset or file.
#pragma once

#include "io/Ingest.h"
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

/// The render volume of @a asset (named @a name in errors).
/// @param minScale  as for GaussianRenderVolume
/// @throw InputError when the voxels it is drawn from (at worst a float grid of its
///        source's size) would not fit in memory.
std::unique_ptr<GaussianRenderVolume> assetRenderVolume(const GaussianAsset& asset, float minScale,
                                                        const std::string& name);

/// Reads @a path: an asset (with only the structures that @a show names, less
/// @a hide) or anything loadOrIngest reads.
/// @param minScale  as for GaussianRenderVolume
/// @throw InputError naming the file, also when @a show or @a hide is given for a grid.
RenderInput loadRenderInput(const std::string& path, const std::string& show, const std::string& hide, float minScale,
                            const IngestOptions& ingest);

/// The transfer function @a tf names: a JSON file, else a preset fitted to @a volume
/// (empty: the preset for data like these). @a mismatch: as for presetFor.
TransferFunction transferFunctionFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch = nullptr);

/// volumeClassifier() of transferFunctionFor().
Classifier classifierFor(const std::string& tf, const RenderVolume& volume, std::string* mismatch = nullptr);

}  // namespace gvr
