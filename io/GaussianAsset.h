/// @file GaussianAsset.h
/// @brief The Gaussian asset file: a fitted model that stands on its own.
///
/// Format, version 1 (all integers little-endian):
///
/// | offset | bytes      | field                                                        |
/// |--------|------------|--------------------------------------------------------------|
/// | 0      | 8          | magic "GVRASSET"                                             |
/// | 8      | 4          | format version, uint32 (1)                                   |
/// | 12     | 4          | header length H, uint32                                      |
/// | 16     | H          | header, UTF-8 JSON (below)                                   |
/// |        | 6 n        | means: 3 x uint16, linear over [mean_min, mean_max] per axis |
/// |        | 4 n        | rotations: uint32 "smallest three" (2-bit index of the       |
/// |        |            | largest component, then three 10-bit components in ±1/√2)    |
/// |        | 6 n        | log-scales: 3 x uint16 over [log_scale_min, log_scale_max]   |
/// |        | n          | opacity: uint8, opacity = (q + 0.5) / 256                    |
/// |        | 2 C n      | colours: C x uint16 over [colour_min, colour_max] per channel|
/// | end-4  | 4          | CRC-32 (zlib) of every byte before it                        |
///
/// The header holds: count n, channels C, cutoff_sigmas, world_from_index (16
/// numbers, OpenVDB's row-vector convention, index space to world mm),
/// value_offset / value_scale (physical = offset + scale * normalised), the
/// quantisation ranges, the source's metadata (including raw_bytes) and the fit
/// settings. Colours are stored after folding the opacity's rounding into them, so
/// the product opacity * colour keeps the colour's precision.
///
/// An asset fitted by structure (`gvr fit --labels`) stores its Gaussians grouped
/// by label, and the header's "labels" lists the groups in order:
/// [{"id": 37, "name": "Hippocampus_L", "count": 412}, ...]. That costs no byte per
/// Gaussian, and readers that ignore the key still read a valid asset.
#pragma once

#include "GaussianParameters.h"
#include "LabelTable.h"
#include "ValueMapping.h"
#include "VolumeMetadata.h"

#include <nlohmann/json.hpp>
#include <openvdb/math/Mat4.h>

#include <cstdint>
#include <string>

namespace gvr {

constexpr std::uint32_t kAssetVersion = 1;

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
};

/// Bytes per stored Gaussian: 17 + 2 * channels.
std::size_t assetBytesPerGaussian(int channels);

/// How many Gaussians fit in @a maxBytes with this asset's header.
std::size_t assetCapacity(const GaussianAsset& asset, std::uint64_t maxBytes);

/// The exact file size @a asset would have.
std::uint64_t assetFileBytes(const GaussianAsset& asset);

/// Writes atomically. With @a maxBytes > 0, the Gaussians with the smallest peak
/// amplitude are dropped first until the file fits.
/// @return the number of Gaussians dropped to fit.
std::size_t writeAsset(const std::string& path, GaussianAsset& asset, std::uint64_t maxBytes = 0);

/// True when the file starts with the asset magic.
bool isAssetFile(const std::string& path);

/// @throw InputError naming @a path for a wrong magic, an unknown version,
///        a size that does not match the header, or a checksum mismatch.
GaussianAsset readAsset(const std::string& path);

/// The asset with only the Gaussians whose label is in @a shown (ascending), and
/// their names; an unlabelled asset is returned whole.
GaussianAsset withLabels(const GaussianAsset& asset, const std::vector<int>& shown);

/// The structures that --show @a show (empty: all) and --hide @a hide leave, by id
/// or name. Nothing is refitted: the other structures' Gaussians are left out.
/// @throw InputError naming @a path when the asset has no labels, or naming the flag
///        for an unknown structure (listing the valid ones).
GaussianAsset selectStructures(const GaussianAsset& asset, const std::string& show, const std::string& hide,
                               const std::string& path);

/// The parameters as they come back from the file (quantised and restored).
GaussianParameters quantisedCopy(const GaussianParameters& params);

}  // namespace gvr
