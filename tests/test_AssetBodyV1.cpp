// Version 1 asset bodies, still loaded: flat arrays of fixed-width quantised
// attributes, decoded from bytes laid out by hand as the format table says.

#include "io/asset/AssetBodyV1.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace gvr {
namespace {

nlohmann::json quantisation() {
    return {{"mean_min", {0.0, 0.0, -2.0}},     {"mean_max", {10.0, 20.0, 2.0}}, {"log_scale_min", {-1.0, -1.0, -1.0}},
            {"log_scale_max", {3.0, 3.0, 3.0}}, {"colour_min", {0.0}},           {"colour_max", {2.0}}};
}

/// Two grey Gaussians, each attribute's array after the other's.
std::string twoGaussians() {
    std::string body;
    body += test::littleEndian16(0) + test::littleEndian16(65535) +
            test::littleEndian16(65535);  // means of Gaussian 0: the ranges' ends
    body += test::littleEndian16(65535) + test::littleEndian16(0) + test::littleEndian16(0);  // Gaussian 1
    // Largest component z (index 3); w, x, y at 10 bits each, highest first.
    body += test::littleEndian32((3u << 30) | (1023u << 20) | (511u << 10) | 511u);
    body += test::littleEndian32((0u << 30) | (0u << 20) | (511u << 10) | 511u);  // largest w
    body += test::littleEndian16(0) + test::littleEndian16(21845) +
            test::littleEndian16(65535);  // log-scales: -1, -1 + 4/3, 3
    body += test::littleEndian16(65535) + test::littleEndian16(65535) + test::littleEndian16(65535);
    body += std::string(1, char(127)) + std::string(1, char(255));  // opacities
    body += test::littleEndian16(65535) + test::littleEndian16(0);  // colours
    return body;
}

TEST(AssetBodyV1, BytesPerGaussianAreSeventeenPlusTwoAChannel) {
    EXPECT_EQ(assetV1BytesPerGaussian(1), 19u);
    EXPECT_EQ(assetV1BytesPerGaussian(3), 23u);
    EXPECT_EQ(twoGaussians().size(), 2 * assetV1BytesPerGaussian(1));
}

TEST(AssetBodyV1, EachArrayDecodesToItsRanges) {
    const GaussianParameters p = decodeAssetBodyV1(twoGaussians(), 2, 1, quantisation());
    ASSERT_EQ(p.count(), 2u);
    EXPECT_EQ(p.channels, 1);
    EXPECT_FLOAT_EQ(p.at(kMeans, 0)[0], 0.0f);
    EXPECT_FLOAT_EQ(p.at(kMeans, 0)[1], 20.0f);
    EXPECT_FLOAT_EQ(p.at(kMeans, 0)[2], 2.0f);
    EXPECT_FLOAT_EQ(p.at(kMeans, 1)[0], 10.0f);
    EXPECT_FLOAT_EQ(p.at(kMeans, 1)[2], -2.0f);
    EXPECT_FLOAT_EQ(p.at(kLogScales, 0)[0], -1.0f);
    EXPECT_NEAR(p.at(kLogScales, 0)[1], 1.0f / 3.0f, 1e-6);
    EXPECT_FLOAT_EQ(p.at(kLogScales, 0)[2], 3.0f);
    EXPECT_FLOAT_EQ(p.at(kColours, 0)[0], 2.0f);
    EXPECT_FLOAT_EQ(p.at(kColours, 1)[0], 0.0f);
}

TEST(AssetBodyV1, RotationsAreUnitQuaternionsWithTheLargestComponentRestored) {
    const GaussianParameters p = decodeAssetBodyV1(twoGaussians(), 2, 1, quantisation());
    const float* q0 = p.at(kRotations, 0);
    // 1023 is the top of the 10-bit range: 1/sqrt(2), the largest a smaller component can be.
    EXPECT_NEAR(q0[0], 1.0 / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(q0[1], 0.0, 1e-3);
    EXPECT_NEAR(q0[2], 0.0, 1e-3);
    EXPECT_NEAR(q0[3], 1.0 / std::sqrt(2.0), 1e-3);
    const float* q1 = p.at(kRotations, 1);
    EXPECT_NEAR(q1[1], -1.0 / std::sqrt(2.0), 1e-6);  // 0 is the bottom: -1/sqrt(2)
    EXPECT_NEAR(q1[2], 0.0, 1e-3);
    EXPECT_NEAR(q1[3], 0.0, 1e-3);
    EXPECT_NEAR(q1[0], 1.0 / std::sqrt(2.0), 1e-3);  // restored, and positive
    for (const float* q : {q0, q1}) {
        EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-5);
    }
}

TEST(AssetBodyV1, OpacitiesAreBinCentresSoEvenTheExtremesHaveFiniteLogits) {
    const GaussianParameters p = decodeAssetBodyV1(twoGaussians(), 2, 1, quantisation());
    const auto opacity = [](float logit) { return 1.0 / (1.0 + std::exp(-double(logit))); };
    EXPECT_NEAR(opacity(*p.at(kOpacityLogits, 0)), 127.5 / 256.0, 1e-6);
    ASSERT_TRUE(std::isfinite(*p.at(kOpacityLogits, 1)));
    EXPECT_NEAR(opacity(*p.at(kOpacityLogits, 1)), 255.5 / 256.0, 1e-6);
}

TEST(AssetBodyV1, ABodyOfTheWrongSizeOrColourRangesOfTheWrongCountAreRefused) {
    const std::string body = twoGaussians();
    EXPECT_THROW(decodeAssetBodyV1(body.substr(0, body.size() - 1), 2, 1, quantisation()), std::runtime_error);
    EXPECT_THROW(decodeAssetBodyV1(body + "x", 2, 1, quantisation()), std::runtime_error);
    EXPECT_THROW(decodeAssetBodyV1(body, 3, 1, quantisation()), std::runtime_error);
    // Two Gaussians of three channels would take 46 bytes.
    EXPECT_THROW(decodeAssetBodyV1(body, 2, 3, quantisation()), std::runtime_error);
    nlohmann::json rgb = quantisation();
    rgb["colour_min"] = {0.0, 0.0};
    rgb["colour_max"] = {1.0, 1.0};
    EXPECT_THROW(decodeAssetBodyV1(body, 2, 1, rgb), std::runtime_error);
    EXPECT_TRUE(decodeAssetBodyV1("", 0, 1, quantisation()).count() == 0);
}

}  // namespace
}  // namespace gvr
