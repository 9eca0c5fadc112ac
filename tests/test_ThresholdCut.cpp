// The threshold rule that export, fit and eval share.

#include "pipeline/Luminance.h"
#include "pipeline/ThresholdCut.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(ThresholdCut, CutsWhatIsAtOrBelowThePhysicalThreshold) {
    const ValueMapping mapping{{-1024.0, -1024.0, -1024.0}, 3000.0};
    const ThresholdCut cut(mapping, 1, -500.0);
    const float justBelow = float(mapping.toNormalised(-500.5, 0)), justAbove = float(mapping.toNormalised(-499.5, 0));
    EXPECT_TRUE(cut.cuts(&justBelow));
    EXPECT_FALSE(cut.cuts(&justAbove));
    float value = justBelow;
    cut.apply(&value);
    EXPECT_EQ(value, 0.0f);  // the background
    EXPECT_FALSE(ThresholdCut().cuts(&justBelow));
}

TEST(ThresholdCut, RgbIsCutOnTheLuminanceOfItsPhysicalValues) {
    const ValueMapping mapping{{10.0, 20.0, 30.0}, 200.0};
    const ThresholdCut cut(mapping, 3, 100.0);
    for (float red : {0.1f, 0.3f, 0.5f, 0.7f}) {
        float rgb[3] = {red, 0.4f, 0.2f};
        double physical[3];
        for (int c = 0; c < 3; ++c) physical[c] = mapping.toPhysical(rgb[c], c);
        EXPECT_EQ(cut.cuts(rgb), luminance(physical) <= 100.0) << red;
    }
}

TEST(ThresholdCut, ABrightBackgroundIsCutFromAbove) {
    const ValueMapping mapping{{250.0, 250.0, 250.0}, -250.0};  // white paper is normalised 0
    const ThresholdCut cut(mapping, 1, std::nullopt, 220.0);
    const float paper = float(mapping.toNormalised(240.0, 0)), specimen = float(mapping.toNormalised(90.0, 0));
    EXPECT_TRUE(cut.cuts(&paper) != cut.cuts(&specimen));
    VolumeMetadata source;
    source.background = 250.0;
    source.thresholdAbove = 220.0;
    EXPECT_EQ(defaultExportThresholdAbove(source), 235.0);
    EXPECT_FALSE(defaultExportThresholdAbove(VolumeMetadata{}));
}

TEST(ThresholdCut, TheDefaultSplitsTheGapBetweenBackgroundAndThreshold) {
    VolumeMetadata source;
    source.valueMin = -3024.0;
    source.background = -1793.0;
    EXPECT_EQ(defaultExportThreshold(source), -3024.0);  // no ingest threshold
    source.threshold = -500.0;
    EXPECT_EQ(defaultExportThreshold(source), -1146.5);
    source.background = -400.0;  // a background above the threshold leaves no gap
    EXPECT_EQ(defaultExportThreshold(source), -500.0);
}

}  // namespace
}  // namespace gvr
