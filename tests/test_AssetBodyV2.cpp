// The format-2 asset body: it decodes to what its round trip promises, within one
// quantisation step of each attribute, and refuses a body of another size.

#include "io/asset/AssetBodyV2.h"
#include "pipeline/GaussianKernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace gvr {
namespace {

/// @a count RGB Gaussians in a 60 x 40 x 30 volume, with negative amplitudes too.
GaussianParameters randomGaussians(std::size_t count) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    GaussianParameters params(count, 3);
    for (std::size_t i = 0; i < count; ++i) {
        const float extent[3] = {60, 40, 30};
        for (int a = 0; a < 3; ++a) params.at(kMeans, i)[a] = extent[a] * unit(random);
        for (int k = 0; k < 4; ++k) params.at(kRotations, i)[k] = unit(random) - 0.5f;
        for (int a = 0; a < 3; ++a) params.at(kLogScales, i)[a] = -1.0f + 2.5f * unit(random);
        *params.at(kOpacityLogits, i) = 4.0f * unit(random) - 2.0f;
        for (int c = 0; c < 3; ++c) params.at(kColours, i)[c] = 1.4f * unit(random) - 0.2f;
    }
    return params;
}

TEST(AssetBodyV2, DecodesToItsRoundTripWithinAStepOfEachAttribute) {
    const GaussianParameters params = randomGaussians(500);
    const AssetEncoding encoding;
    const QuantisationV2 quantisation(params, encoding);
    AttributeBytes parts;
    const std::string body = encodeAssetBodyV2(params, quantisation, &parts);
    const GaussianParameters decoded = decodeAssetBodyV2(body, params.count(), quantisation);
    const GaussianParameters expected = roundTripAssetBodyV2(params, quantisation);
    ASSERT_EQ(decoded.count(), params.count());
    for (int g = 0; g < kGroupCount; ++g)
        EXPECT_EQ(decoded.values[g], expected.values[g]) << groupName(ParameterGroup(g));
    EXPECT_GT(parts.position, 0u);
    EXPECT_LE(parts.position + parts.rotation + parts.logScales + parts.amplitudes, body.size());

    // The body keeps the given order; compare each Gaussian with its own.
    for (std::size_t i = 0; i < params.count(); ++i) {
        for (int a = 0; a < 3; ++a) {
            const float logScaleStep =
                (quantisation.logScaleMax[a] - quantisation.logScaleMin[a]) / float((1 << encoding.logScaleBits) - 1);
            EXPECT_NEAR(decoded.at(kMeans, i)[a], params.at(kMeans, i)[a], 0.5f * encoding.meanStep + 1e-4f);
            EXPECT_NEAR(decoded.at(kLogScales, i)[a], params.at(kLogScales, i)[a], 0.5f * logScaleStep + 1e-5f);
        }
        const float amplitude = sigmoid(*params.at(kOpacityLogits, i)) * params.at(kColours, i)[1];
        const float decodedAmplitude = sigmoid(*decoded.at(kOpacityLogits, i)) * decoded.at(kColours, i)[1];
        const float amplitudeStep =
            (quantisation.amplitudeMax[1] - quantisation.amplitudeMin[1]) / float((1 << encoding.amplitudeBits) - 1);
        EXPECT_NEAR(decodedAmplitude, amplitude, 0.5f * amplitudeStep + 1e-5f) << i;
    }
}

TEST(AssetBodyV2, TheQuantisationRecordRoundTripsThroughJson) {
    const GaussianParameters params = randomGaussians(50);
    const QuantisationV2 original(params, AssetEncoding{});
    const QuantisationV2 read(original.json(), 3);
    EXPECT_EQ(read.json(), original.json());
    EXPECT_EQ(read.meanBits, original.meanBits);
    nlohmann::json missing = original.json(), impossible = original.json();
    missing.erase("mean_bits");
    EXPECT_THROW(QuantisationV2(missing, 3), nlohmann::json::exception);
    impossible["mean_bits"] = 99;
    EXPECT_THROW(QuantisationV2(impossible, 3), std::runtime_error);
    EXPECT_THROW(QuantisationV2(original.json(), 1), std::runtime_error);  // ranges for three channels
}

TEST(AssetBodyV2, ABodyOfAnotherCountIsRefused) {
    const GaussianParameters params = randomGaussians(40);
    const QuantisationV2 quantisation(params, AssetEncoding{});
    const std::string body = encodeAssetBodyV2(params, quantisation);
    EXPECT_THROW(decodeAssetBodyV2(body, 41, quantisation), std::runtime_error);
    EXPECT_THROW(decodeAssetBodyV2(body.substr(0, body.size() / 2), 40, quantisation), std::runtime_error);
}

}  // namespace
}  // namespace gvr
