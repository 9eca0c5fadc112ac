#include "io/asset/AssetBodyV1.h"

#include "io/asset/Quantisation.h"
#include "io/guard/ByteOrder.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gvr {

namespace {

float dequantise16(std::uint16_t q, float lo, float hi) { return dequantise(q, lo, hi, 16); }

/// Format 1 packs the largest component's index in the top two bits and the other
/// three in 10 bits each, highest first.
void unpackQuaternion(std::uint32_t packed, float q[4]) {
    const int largest = int(packed >> 30);
    int shift = 20;
    for (int k = 0; k < 4; ++k) {
        if (k == largest) continue;
        const float t = float((packed >> shift) & 1023u) / 1023.0f;
        q[k] = float((2.0 * t - 1.0) / M_SQRT2);
        shift -= 10;
    }
    completeQuaternion(largest, q);
}

}  // namespace

std::size_t assetV1BytesPerGaussian(int channels) { return 17 + 2 * std::size_t(channels); }

GaussianParameters decodeAssetBodyV1(std::string_view body, std::size_t count, int channels,
                                     const nlohmann::json& quantisation) {
    if (body.size() != count * assetV1BytesPerGaussian(channels)) {
        throw std::runtime_error("the body's size does not match the Gaussian count");
    }
    const auto meanMin = quantisation.at("mean_min").get<std::array<float, 3>>();
    const auto meanMax = quantisation.at("mean_max").get<std::array<float, 3>>();
    const auto scaleMin = quantisation.at("log_scale_min").get<std::array<float, 3>>();
    const auto scaleMax = quantisation.at("log_scale_max").get<std::array<float, 3>>();
    const auto colourMin = quantisation.at("colour_min").get<std::vector<float>>();
    const auto colourMax = quantisation.at("colour_max").get<std::vector<float>>();
    if (int(colourMin.size()) != channels || int(colourMax.size()) != channels) {
        throw std::runtime_error("colour ranges do not match the channel count");
    }
    const char* cursor = body.data();
    GaussianParameters params(count, channels);
    for (std::size_t i = 0; i < count; ++i) {
        for (int a = 0; a < 3; ++a)
            params.at(kMeans, i)[a] = dequantise16(takeLittleEndian<std::uint16_t>(cursor), meanMin[a], meanMax[a]);
    }
    for (std::size_t i = 0; i < count; ++i)
        unpackQuaternion(takeLittleEndian<std::uint32_t>(cursor), params.at(kRotations, i));
    for (std::size_t i = 0; i < count; ++i) {
        for (int a = 0; a < 3; ++a) {
            params.at(kLogScales, i)[a] =
                dequantise16(takeLittleEndian<std::uint16_t>(cursor), scaleMin[a], scaleMax[a]);
        }
    }
    for (std::size_t i = 0; i < count; ++i) {
        const float opacity = (takeLittleEndian<std::uint8_t>(cursor) + 0.5f) / 256.0f;
        *params.at(kOpacityLogits, i) = std::log(opacity / (1.0f - opacity));
    }
    for (std::size_t i = 0; i < count; ++i) {
        for (int c = 0; c < channels; ++c) {
            params.at(kColours, i)[c] =
                dequantise16(takeLittleEndian<std::uint16_t>(cursor), colourMin[c], colourMax[c]);
        }
    }
    return params;
}

}  // namespace gvr
