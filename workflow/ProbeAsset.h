/// @file ProbeAsset.h
/// @brief What `gvr probe` and Python's `asset.probe` report: an asset's values at
/// points of its source's index space, from its Gaussians or, with its residual
/// layer, from its bounded reconstruction.
#pragma once

#include "io/asset/AssetExport.h"
#include "pipeline/AssetProbe.h"

#include <array>
#include <string>
#include <vector>

namespace gvr {

/// @a layers of @a asset (named @a name in errors) at index-space @a points. With the
/// residual layer a value is its reconstruction's, trilinear between voxel centres
/// (at a voxel centre that voxel's, within the bound of the source) and the
/// background beyond the source's voxels; `gaussians` counts the Gaussians that
/// reach the point either way.
/// @throw InputError as boundedReconstruction.
std::vector<AssetProbe::Sample> probeAsset(const GaussianAsset& asset, const std::vector<std::array<double, 3>>& points,
                                           AssetLayers layers, const std::string& name,
                                           const ProgressFn& progress = {});

}  // namespace gvr
