/// @file AssetBodyV1.h
/// @brief Reads the body of a version 1 asset: flat, fixed-width quantised arrays.
///
/// | bytes | field                                                                  |
/// |-------|------------------------------------------------------------------------|
/// | 6 n   | means: 3 x uint16, linear over [mean_min, mean_max] per axis           |
/// | 4 n   | rotations: uint32 "smallest three" (2-bit index of the largest         |
/// |       | component, then three 10-bit components in ±1/√2)                      |
/// | 6 n   | log-scales: 3 x uint16 over [log_scale_min, log_scale_max]             |
/// | n     | opacity: uint8, opacity = (q + 0.5) / 256                              |
/// | 2 C n | colours: C x uint16 over [colour_min, colour_max] per channel          |
///
/// gvr writes version 2 (AssetBodyV2.h) since 2026-11-23; version 1 files still load.
#pragma once

#include "pipeline/GaussianParameters.h"

#include <nlohmann/json.hpp>

#include <string_view>

namespace gvr {

/// Bytes per Gaussian in a version 1 body: 17 + 2 * channels.
std::size_t assetV1BytesPerGaussian(int channels);

/// @a quantisation is the header's "quantisation" object.
/// @throw std::runtime_error when @a body does not hold exactly @a count Gaussians.
GaussianParameters decodeAssetBodyV1(std::string_view body, std::size_t count, int channels,
                                     const nlohmann::json& quantisation);

}  // namespace gvr
