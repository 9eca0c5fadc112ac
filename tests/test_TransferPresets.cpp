// The named transfer functions: which one suits which data, and what each shows.

#include "render/TransferPresets.h"

#include <gtest/gtest.h>

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

TEST(TransferPresets, TheDefaultFollowsTheData) {
    EXPECT_EQ(defaultPreset(3, statisticsOf({0.0f, 100.0f}, 0.0)), "rgb");
    EXPECT_EQ(defaultPreset(1, statisticsOf({-1024.0f, 40.0f, 1200.0f}, -1024.0)), "ct");
    EXPECT_EQ(defaultPreset(1, statisticsOf({0.0f, 40.0f, 255.0f}, 0.0)), "mri");
}

TEST(TransferPresets, BoneIsTransparentBelowItsWindowAndOpaqueAboveIt) {
    const TransferFunction bone = presetTransferFunction("ct-bone", statisticsOf({-1024.0f, 0.0f, 1500.0f}, -1024.0));
    EXPECT_EQ(bone(0.0)[3], 0.0f);      // soft tissue
    EXPECT_EQ(bone(-1000.0)[3], 0.0f);  // air
    EXPECT_GT(bone(1000.0)[3], 0.0f);   // cortical bone
}

TEST(TransferPresets, AnUnknownPresetIsNamedAndThePresetsListed) {
    const auto message = [] {
        try {
            presetTransferFunction("bones", statisticsOf({0.0f, 1.0f}, 0.0));
        } catch (const std::exception& error) {
            return std::string(error.what());
        }
        return std::string("accepted");
    }();
    EXPECT_NE(message.find("bones"), std::string::npos) << message;
    for (const char* preset : {"ct", "ct-bone", "mri", "rgb"})
        EXPECT_NE(message.find(preset), std::string::npos) << message;
}

}  // namespace
}  // namespace gvr
