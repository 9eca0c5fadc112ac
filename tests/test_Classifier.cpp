// The classifier every renderer shares: grey values through the transfer function,
// colour samples scaled and clamped with opacity from their luminance, and opacity
// over a path length.

#include "pipeline/Luminance.h"
#include "render/Classifier.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

const TransferFunction ramp({{0, {0, 0, 0, 0}}, {100, {1, 0.5f, 0.25f, 0.8f}}}, "ramp");

TEST(Classifier, GreyValuesGoThroughTheTransferFunction) {
    const Classifier classify(ramp, 1);
    const float value = 50.0f;
    const std::array<float, 4> rgba = classify(&value);
    EXPECT_FLOAT_EQ(rgba[0], 0.5f);
    EXPECT_FLOAT_EQ(rgba[1], 0.25f);
    EXPECT_FLOAT_EQ(rgba[3], 0.4f);
    const float below = -1000.0f;  // Hounsfield air, below the function's first point
    EXPECT_EQ(classify(&below)[3], 0.0f);
}

TEST(Classifier, ColourKeepsTheSampleScaledAndTakesOpacityFromLuminance) {
    const Classifier classify(ramp, 3, 1.0 / 200.0);
    const float sample[3] = {100.0f, 50.0f, 400.0f};
    const std::array<float, 4> rgba = classify(sample);
    EXPECT_FLOAT_EQ(rgba[0], 0.5f);
    EXPECT_FLOAT_EQ(rgba[1], 0.25f);
    EXPECT_FLOAT_EQ(rgba[2], 1.0f);  // clamped
    EXPECT_FLOAT_EQ(rgba[3], ramp(luminance(sample))[3]);
}

TEST(Classifier, OpacityCompoundsOverAPath) {
    EXPECT_FLOAT_EQ(opacityOverLength(0.5f, 1.0), 0.5f);
    EXPECT_FLOAT_EQ(opacityOverLength(0.5f, 2.0), 0.75f);
    EXPECT_NEAR(opacityOverLength(0.5f, 0.5), 1.0 - std::sqrt(0.5), 1e-7);
    EXPECT_EQ(opacityOverLength(1.0f, 0.1), 1.0f);
    EXPECT_EQ(opacityOverLength(0.0f, 10.0), 0.0f);
}

}  // namespace
}  // namespace gvr
