/// @file AssetFile.h
/// @brief The Gaussian asset file: a GaussianAsset (pipeline/GaussianAsset.h) on disk.
///
/// Format, version 2 (all integers little-endian):
///
/// | offset | bytes | field                                                          |
/// |--------|-------|----------------------------------------------------------------|
/// | 0      | 8     | magic "GVRASSET"                                               |
/// | 8      | 4     | format version, uint32 (2, or 3 with a residual layer; 1 loads)|
/// | 12     | 4     | header length H, uint32                                        |
/// | 16     | H     | header, UTF-8 JSON (below)                                     |
/// |        | B     | body: the Gaussians, quantised and entropy-coded (AssetBodyV2.h)|
/// |        | R     | version 3: the residual layer (AssetResidual.h)                |
/// | end-4  | 4     | CRC-32 (zlib) of every byte before it                          |
///
/// The header holds: count n, channels C, cutoff_sigmas, world_from_index (16
/// numbers, OpenVDB's row-vector convention, index space to world mm),
/// value_offset / value_scale (physical = offset + scale * normalised), the
/// quantisation (ranges and bit depths), the source's metadata (including
/// raw_bytes) and the fit settings. Version 1 (AssetBodyV1.h) stored the body as
/// flat fixed-width arrays, 17 + 2C bytes per Gaussian.
///
/// An asset fitted by structure (`gvr fit --labels`) stores its Gaussians grouped
/// by label, and the header's "labels" lists the groups in order:
/// [{"id": 37, "name": "Hippocampus_L", "count": 412}, ...]. That costs no byte per
/// Gaussian, and readers that ignore the key still read a valid asset.
#pragma once

#include "io/asset/AssetBodyV2.h"
#include "pipeline/GaussianAsset.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace gvr {

/// The first bytes of every asset file (fileKind() tells assets by them).
inline constexpr char kAssetMagic[8] = {'G', 'V', 'R', 'A', 'S', 'S', 'E', 'T'};

constexpr std::uint32_t kAssetVersion = 2;  ///< the version gvr writes
/// Version 2 with a residual layer (io/asset/AssetResidual.h) after the Gaussians' body,
/// described by the header's "residual".
constexpr std::uint32_t kBoundedAssetVersion = 3;

/// What a Gaussian costs in this asset's file, on average, when it holds @a count
/// Gaussians over its source's voxels: for budgets before the fit, since the entropy
/// coder decides the exact size (estimatedBytesPerGaussian).
double assetEstimatedBytesPerGaussian(const GaussianAsset& asset, double count);

/// About how many Gaussians fit in @a maxBytes with this asset's header.
std::size_t assetCapacity(const GaussianAsset& asset, std::uint64_t maxBytes);

/// The exact file size @a asset would have.
std::uint64_t assetFileBytes(const GaussianAsset& asset);

/// About how many more Gaussians, each coded as the asset's average one now is, fit
/// in @a maxBytes: 0 once the file is that large. Puts @a asset into storage order,
/// as encodeAsset() does.
std::size_t assetRoom(GaussianAsset& asset, std::uint64_t maxBytes);

/// Writes atomically, in the current version. The Gaussians are put into storage
/// order (label groups kept, Morton order inside). With @a maxBytes > 0, the
/// Gaussians with the smallest peak amplitude are dropped first until the file fits.
/// @return the number of Gaussians dropped to fit.
std::size_t writeAsset(const std::string& path, GaussianAsset& asset, std::uint64_t maxBytes = 0);

/// What writeAsset() does to @a asset before writing: storage order, and the
/// weakest Gaussians dropped until the file fits in @a maxBytes (0: no limit).
/// @return the number of Gaussians dropped.
std::size_t fitAssetInto(GaussianAsset& asset, std::uint64_t maxBytes);

/// fitAssetInto(), for a caller that then writes the file (writeAssetBytes()).
/// @return the file's bytes.
std::string encodeAssetWithin(GaussianAsset& asset, std::uint64_t maxBytes);

/// The whole file for @a asset, which is put into storage order first: the
/// Gaussians (format 2), and its residual layer after them when it has one
/// (format 3; withResidualLayer() adds a new one).
std::string encodeAsset(GaussianAsset& asset);

/// @a assetBytes (a format-2 file, as encodeAsset() gave it) with @a layer after its
/// Gaussians, as format 3. The Gaussians' bytes are kept as they are, since the layer
/// was encoded over the field that exactly these bytes decode to.
std::string withResidualLayer(std::string_view assetBytes, const ResidualLayer& layer);

/// Writes the bytes of encodeAsset() atomically, for a caller that also needs them
/// (to send them to MPI ranks, say) and would otherwise encode twice.
void writeAssetBytes(const std::string& path, const std::string& bytes);

/// An asset from the bytes of a whole file (sent over MPI, say), checked as
/// readAsset() checks a file.
/// @throw InputError naming @a name, as readAsset() does.
GaussianAsset decodeAsset(std::string_view bytes, const std::string& name);

/// @throw InputError naming @a path for a wrong magic, an unknown version,
///        a size that does not match the header, or a checksum mismatch.
GaussianAsset readAsset(const std::string& path);

/// The parameters as they come back from a file written with @a encoding
/// (quantised and restored, in the same order).
GaussianParameters quantisedCopy(const GaussianParameters& params, const AssetEncoding& encoding = {});

}  // namespace gvr
