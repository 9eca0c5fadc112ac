/// @file AssetResidual.h
/// @brief The residual layer's section of an asset file (format 3): after the
/// Gaussians' body, two length-prefixed zstd frames and one range-coded stream per
/// slab, described by the header's "residual" object.
///
/// | part         | holds                                                              |
/// |--------------|--------------------------------------------------------------------|
/// | predictors   | zstd frame: one byte per 8^3 block and channel (ResidualPredictor) |
/// | exact        | zstd frame: the exact voxels' values (stored samples or values),   |
/// |              | float64                                                            |
/// | codes        | per slab, a uint64 byte count and its stream (io/asset/ResidualCodes)    |
///
/// The header's "residual": bound, domain ("integers" with slope and intercept, or
/// "values"), slab_slices, coder ("range-contexts"), exact_voxels, section_bytes and
/// reconstruction_crc32 (zlib's CRC-32 of the reconstruction's float32 values).
#pragma once

#include "pipeline/ResidualLayer.h"

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace gvr {

/// The section's bytes; @a description receives the header's "residual" object.
std::string encodeResidualSection(const ResidualLayer& layer, nlohmann::json& description);

/// The layer of a section described by @a description, over a source of @a dims and
/// @a channels (the asset's). @throw std::runtime_error for anything inconsistent,
/// checked before anything is allocated.
ResidualLayer decodeResidualSection(std::string_view section, const nlohmann::json& description,
                                    const openvdb::Coord& dims, int channels);

/// zlib's CRC-32 of @a volume's float values, as reconstruction_crc32 holds it.
std::uint32_t reconstructionChecksum(const FloatVolume& volume);

}  // namespace gvr
