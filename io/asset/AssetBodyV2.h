/// @file AssetBodyV2.h
/// @brief The body of a version 2 asset: quantised attributes, entropy-coded.
///
/// Only what the field needs is stored: a mean, a rotation, three log-scales and one
/// amplitude (opacity * colour) per channel. Each attribute is quantised to an integer
/// (bit depths in AssetEncoding, chosen by measuring rate against distortion), split
/// into byte planes, and each plane is one zstd frame. Means are coded as the
/// difference between consecutive Morton codes, so Gaussians stored in Morton order
/// (writeAsset sorts them) cost about log2(cells / Gaussians) bits for their position.
///
/// | field             | integers per Gaussian                                        |
/// |-------------------|--------------------------------------------------------------|
/// | position          | Morton code of the mean on a lattice of `mean_step` voxels,  |
/// |                   | minus the previous Gaussian's, modulo 2^(3 * mean_bits)      |
/// | rotation          | index of the largest quaternion component (0-3), then the    |
/// |                   | other three in ±1/√2, `rotation_bits` each (largest made ≥ 0)|
/// | log-scales        | 3 x `log_scale_bits` over [log_scale_min, log_scale_max]      |
/// | amplitudes        | C x `amplitude_bits` over [amplitude_min, amplitude_max]      |
///
/// The body is the planes in that order, each as a uint32 length then a zstd frame
/// whose content is exactly one byte per Gaussian.
#pragma once

#include "pipeline/AssetEncoding.h"
#include "pipeline/GaussianParameters.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gvr {

/// Ranges and bit depths of one asset: the header's "quantisation" object.
struct QuantisationV2 {
    AssetEncoding encoding;
    int meanBits = 0;  ///< per axis, so that every mean's lattice index fits
    std::array<float, 3> meanMin{}, logScaleMin{}, logScaleMax{};
    std::array<float, 3> amplitudeMin{}, amplitudeMax{};
    int channels = 1;

    /// The ranges that @a params need.
    QuantisationV2(const GaussianParameters& params, const AssetEncoding& encoding);
    /// @throw nlohmann::json::exception for a missing or mistyped key, std::runtime_error
    ///        for an impossible value (AssetFile names the file for either).
    QuantisationV2(const nlohmann::json& json, int channels);

    nlohmann::json json() const;
    /// The Morton code of a mean on the lattice: the key of the storage order.
    std::uint64_t mortonCode(const float mean[3]) const;
};

/// About how many bytes one Gaussian takes in a body of @a count Gaussians spread
/// over @a voxels voxels: an empirical model of the entropy coder (positions cost
/// about log2(lattice cells / count) + 2.5 bits, the other attributes a little under
/// their width), fitted to fits of ch2 and ct-head (README, "Asset format"). Budgets
/// before a fit use it; the writer then trims to the exact size.
double estimatedBytesPerGaussian(const AssetEncoding& encoding, int channels, double voxels, double count);

/// Compressed bytes of each attribute in a body, for rate-distortion tables.
struct AttributeBytes {
    std::size_t position = 0, rotation = 0, logScales = 0, amplitudes = 0;
};

/// The compressed body for @a params, in their order; @a bytes, if given, gets what
/// each attribute took (plane headers included).
std::string encodeAssetBodyV2(const GaussianParameters& params, const QuantisationV2& quantisation,
                              AttributeBytes* bytes = nullptr);

/// What decodeAssetBodyV2(encodeAssetBodyV2(params)) gives, without compressing.
GaussianParameters roundTripAssetBodyV2(const GaussianParameters& params, const QuantisationV2& quantisation);

/// @throw std::runtime_error when @a body is not exactly @a count Gaussians' planes.
GaussianParameters decodeAssetBodyV2(std::string_view body, std::size_t count, const QuantisationV2& quantisation);

}  // namespace gvr
