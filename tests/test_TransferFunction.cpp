// The piecewise-linear transfer function: interpolation, clamping and its transparent range.

#include "TransferFunction.h"
#include "TransferPresets.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

TEST(TransferFunction, InterpolatesAndHoldsItsEnds) {
    const TransferFunction tf({{0, {0, 0, 0, 0}}, {10, {1, 0.5f, 0, 1}}}, "t");
    EXPECT_FLOAT_EQ(tf(2.5)[0], 0.25f);
    EXPECT_FLOAT_EQ(tf(2.5)[1], 0.125f);
    EXPECT_EQ(tf(-100)[3], 0.0f);
    EXPECT_EQ(tf(100)[3], 1.0f);
}

TEST(TransferFunction, TransparentUpToTheLastZeroOpacityPoint) {
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0}}, {20, {1, 1, 1, 0}}, {30, {1, 1, 1, 1}}}, "t").transparentUpTo(), 20.0);
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0.1f}}, {30, {1, 1, 1, 1}}}, "t").transparentUpTo(), -INFINITY);
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0}}, {30, {1, 1, 1, 0}}}, "t").transparentUpTo(), INFINITY);
}

}  // namespace
}  // namespace gvr

namespace gvr {
namespace {

VolumeStatistics statisticsOf(std::vector<float> values, double background) {
    VolumeStatistics statistics;
    statistics.values = std::move(values);
    statistics.background = background;
    statistics.hounsfield = background < -500.0;
    return statistics;
}

TEST(TransferPresets, AHounsfieldPresetOnDataWithoutHuSaysWhichPresetFits) {
    const VolumeStatistics eightBit = statisticsOf({0.0f, 40.0f, 255.0f}, 0.0);
    const std::string problem = presetMismatch("ct", 1, eightBit);
    EXPECT_NE(problem.find("Hounsfield"), std::string::npos) << problem;
    EXPECT_NE(problem.find("(0 to 255)"), std::string::npos) << problem;
    EXPECT_NE(problem.find("mri fits them"), std::string::npos) << problem;
    EXPECT_NE(presetMismatch("ct-bone", 1, eightBit), "");
    EXPECT_EQ(presetMismatch("mri", 1, eightBit), "");

    const VolumeStatistics hounsfield = statisticsOf({-1024.0f, -300.0f, 1200.0f}, -1024.0);
    EXPECT_EQ(presetMismatch("ct", 1, hounsfield), "");
    EXPECT_EQ(presetMismatch("ct-bone", 1, hounsfield), "");
    EXPECT_EQ(presetMismatch("mri", 1, hounsfield), "");  // a window of the percentiles suits HU too
}

TEST(TransferPresets, ColourPresetsAndGreyPresetsKeepToTheirData) {
    const VolumeStatistics grey = statisticsOf({0.0f, 100.0f}, 0.0);
    EXPECT_FALSE(presetTakes("rgb", 1));
    EXPECT_TRUE(presetTakes("rgb", 3));
    EXPECT_FALSE(presetTakes("mri", 3));
    EXPECT_NE(presetMismatch("rgb", 1, grey).find("mri fits them"), std::string::npos);
    EXPECT_NE(presetMismatch("ct", 3, grey).find("rgb fits them"), std::string::npos);
}

}  // namespace
}  // namespace gvr
