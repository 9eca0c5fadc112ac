// Value levels and codes: the levels span the transfer function and know where it
// can be seen; the codes span a slice's values evenly, within reach of it.

#include "render/ValueLevels.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace gvr {
namespace {

TEST(ValueLevels, ValueLevelsSpanTheTransferFunctionAndKnowWhereItCanBeSeen) {
    const ValueLevels levels(
        TransferFunction({{-1000.0, {0, 0, 0, 0}}, {0.0, {0, 0, 0, 0}}, {3095.0, {1, 1, 1, 1}}}, "test"), 2.0);
    EXPECT_EQ(levels.levelOf(-5000.0f), 0);
    EXPECT_EQ(levels.levelOf(-1000.0f), 0);
    EXPECT_EQ(levels.levelOf(3095.0f), ValueLevels::kCount - 1);
    EXPECT_EQ(levels.levelOf(1e30f), ValueLevels::kCount - 1);
    EXPECT_EQ(levels.levelOf(0.0f), 1000);  // one level a value here
    // Opacity over two voxels of slice spacing, colour straight.
    const std::array<float, 4> mid = levels.rgba(levels.levelOf(1547.5f));
    EXPECT_NEAR(mid[0], 0.5f, 1e-3f);
    EXPECT_NEAR(mid[3], 1.0f - 0.25f, 1e-3f);
    EXPECT_FALSE(levels.anyVisible(-1e6f, 0.0f));
    EXPECT_TRUE(levels.anyVisible(-1e6f, 1.0f));
    EXPECT_TRUE(levels.anyVisible(3000.0f, 1e6f));
    // Level 1000 (the value 0) is the last transparent one: fractional levels from
    // halfway to the next are seen.
    EXPECT_EQ(levels.darkBelow(), 1000.5f);
    EXPECT_EQ(levels.rgba(ValueLevels::nearest(std::nextafter(1000.5f, 0.0f)))[3], 0.0f);
    EXPECT_GT(levels.rgba(ValueLevels::nearest(1000.5f))[3], 0.0f);
    EXPECT_EQ(ValueLevels::nearest(-1e6f), 0);
    EXPECT_EQ(ValueLevels::nearest(1e6f), ValueLevels::kCount - 1);
}

TEST(ValueLevels, ValueLevelsAreDarkBelowNothingWhenLevelZeroIsSeenAndBelowEverythingWhenNoneIs) {
    const ValueLevels seen(TransferFunction({{0.0, {1, 1, 1, 0.1f}}, {10.0, {1, 1, 1, 1}}}, "test"), 1.0);
    EXPECT_EQ(seen.darkBelow(), -INFINITY);
    const ValueLevels clear(TransferFunction({{0.0, {1, 1, 1, 0}}, {10.0, {1, 1, 1, 0}}}, "test"), 1.0);
    EXPECT_EQ(clear.darkBelow(), INFINITY);
}

TEST(ValueLevels, ValueCodesSpanTheirValuesEvenly) {
    // Hounsfield units, and a window of 200 of them.
    const ValueLevels levels(TransferFunction({{100.0, {1, 1, 1, 0}}, {300.0, {1, 1, 1, 1}}}, "test"), 1.0);
    const ValueCoding coding = levels.codingFor(-1024.0f, 3071.0f);
    EXPECT_EQ(coding.code(-1024.0f), 0);
    EXPECT_EQ(coding.code(3071.0f), ValueCoding::kLastCode);
    EXPECT_EQ(coding.code(-5000.0f), 0);
    EXPECT_EQ(coding.code(5000.0f), ValueCoding::kLastCode);
    const double halfCode = 0.5 * 4095.0 / ValueCoding::kLastCode;
    for (float value : {-1024.0f, -1000.0f, -0.5f, 0.0f, 100.0f, 123.456f, 299.99f, 3071.0f}) {
        EXPECT_NEAR(coding.value(coding.code(value)), value, halfCode * 1.0001) << value;
        // A code's level is its value's, fractionally: 4095 levels over the window.
        const double level = (value - 100.0) * 4095.0 / 200.0;
        EXPECT_NEAR(coding.level(coding.code(value)), level, halfCode * 4095.0 / 200.0 * 1.0001 + 1e-3) << value;
        // Less than a level off: the nearest level may differ by one.
        EXPECT_LE(std::abs(ValueLevels::nearest(coding.level(coding.code(value))) - levels.levelOf(value)), 1) << value;
    }
}

TEST(ValueLevels, ValueCodesReachNoFurtherThanSixtyFourSpansBeyondTheTransferFunction) {
    // A window one unit wide, and values from minus to plus the float range: codes
    // spread over them all would leave the window none.
    const ValueLevels levels(TransferFunction({{0.0, {1, 1, 1, 0}}, {1.0, {1, 1, 1, 1}}}, "test"), 1.0);
    const ValueCoding coding = levels.codingFor(-FLT_MAX, FLT_MAX);
    EXPECT_EQ(coding.code(-64.0f), 0);
    EXPECT_EQ(coding.code(65.0f), ValueCoding::kLastCode);
    EXPECT_GT(coding.code(0.25f) - coding.code(0.0f), 100);
    // 129 spans of 4095 levels in 65535 codes: within half a code, 4.03 levels.
    EXPECT_NEAR(coding.level(coding.code(0.5f)), 2047.5f, 0.5 * 129 * 4095 / 65535.0 + 0.02);
    // Beyond the reach, values classify as the end levels all the same.
    EXPECT_EQ(ValueLevels::nearest(coding.level(coding.code(-1e30f))), 0);
    EXPECT_EQ(ValueLevels::nearest(coding.level(coding.code(1e30f))), ValueLevels::kCount - 1);
}

TEST(ValueLevels, ValueCodesOfOneValueStandForIt) {
    const ValueLevels levels(TransferFunction({{0.0, {1, 1, 1, 0}}, {4095.0, {1, 1, 1, 1}}}, "test"), 1.0);
    const ValueCoding coding = levels.codingFor(7.0f, 7.0f);
    EXPECT_EQ(coding.code(7.0f), 0);
    EXPECT_EQ(coding.value(0.0f), 7.0);
    EXPECT_FLOAT_EQ(coding.level(0.0f), 7.0f);
    // A transfer function of one value has one level.
    const ValueLevels point(TransferFunction({{5.0, {1, 1, 1, 1}}}, "test"), 1.0);
    EXPECT_EQ(point.codingFor(-1.0f, 1e30f).level(30000.0f), 0.0f);
}

}  // namespace
}  // namespace gvr
