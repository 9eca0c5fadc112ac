/// @file GaussianAsset.h
/// @brief A fitted model that stands on its own: the Gaussians with everything
/// needed to place them in the world, map their values back to the source's
/// units, and name their structures. io/asset/AssetFile.h stores it.
#pragma once

#include "pipeline/AssetEncoding.h"
#include "pipeline/GaussianParameters.h"
#include "pipeline/LabelTable.h"
#include "pipeline/ResidualLayer.h"
#include "pipeline/ValueMapping.h"
#include "pipeline/VolumeMetadata.h"

#include <nlohmann/json.hpp>
#include <openvdb/math/Mat4.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gvr {

struct GaussianAsset {
    GaussianParameters params;
    /// Empty, or one label per Gaussian, grouped (all of one label together).
    std::vector<int> labels;
    LabelTable labelTable;  ///< names of the labels in @a labels
    float cutoffSigmas = 3.0f;
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
    ValueMapping mapping;
    VolumeMetadata source;
    nlohmann::json fitSettings = nlohmann::json::object();
    AssetEncoding encoding;  ///< bit depths for storing
    /// The error-bounded layer over the Gaussians on the source's lattice, or null
    /// (pipeline/ResidualLayer.h). Shared: copies of an asset do not copy its codes.
    std::shared_ptr<const ResidualLayer> residual;
    std::uint32_t formatVersion = 0;  ///< the file version it was read from (0: not read)
};

/// Keeps the Gaussians (and their labels) whose flag is set, in order; drops the
/// residual layer, which corrected the field of them all.
void keepOnly(GaussianAsset& asset, const std::vector<bool>& keep);

/// Drops the Gaussians with the smallest peak amplitude max_c |opacity * colour_c|,
/// keeping @a keepCount, in their order.
void keepStrongest(GaussianAsset& asset, std::size_t keepCount);

/// The asset with only the Gaussians whose label is in @a shown (ascending), and
/// their names; an unlabelled asset is returned whole.
GaussianAsset withLabels(const GaussianAsset& asset, const std::vector<int>& shown);

/// The structures that --show @a show (empty: all) and --hide @a hide leave, by id
/// or name. Nothing is refitted: the other structures' Gaussians are left out.
/// @throw InputError naming @a path when the asset has no labels, or naming the flag
///        for an unknown structure (listing the valid ones).
GaussianAsset selectStructures(const GaussianAsset& asset, const std::string& show, const std::string& hide,
                               const std::string& path);

}  // namespace gvr
