// Normalised fit values to physical units and back: Hounsfield offsets, and
// saturation at the float range instead of infinity.

#include "pipeline/ValueMapping.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace gvr {
namespace {

TEST(ValueMapping, MapsBackAndForthWithNegativeOffsets) {
    ValueMapping hounsfield;
    hounsfield.offset = {-1024.0, 0.0, 0.0};  // background: air
    hounsfield.scale = 4095.0;
    EXPECT_DOUBLE_EQ(hounsfield.toPhysical(0.0, 0), -1024.0);
    EXPECT_DOUBLE_EQ(hounsfield.toPhysical(1.0, 0), 3071.0);
    EXPECT_NEAR(hounsfield.toNormalised(hounsfield.toPhysical(0.3, 0), 0), 0.3, 1e-15);
}

TEST(ValueMapping, AFloatGridSaturatesInsteadOfOverflowing) {
    ValueMapping huge;
    huge.scale = 3e38;
    EXPECT_EQ(huge.toPhysicalFloat(10.0, 0), FLT_MAX);
    EXPECT_EQ(huge.toPhysicalFloat(-10.0, 0), -FLT_MAX);
    EXPECT_TRUE(std::isfinite(huge.toPhysicalFloat(1e300, 0)));
    EXPECT_FLOAT_EQ(huge.toPhysicalFloat(0.5, 0), 1.5e38f);
}

}  // namespace
}  // namespace gvr
