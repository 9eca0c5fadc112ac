// Rec. 709 luma: the weights sum to one, so grey stays grey, and any indexable
// colour type gives the same answer.

#include "pipeline/Luminance.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <array>
#include <cmath>
#include <limits>

namespace gvr {
namespace {

TEST(Luminance, PrimariesGiveTheirWeights) {
    EXPECT_DOUBLE_EQ(luminance(std::array<double, 3>{1.0, 0.0, 0.0}), 0.2126);
    EXPECT_DOUBLE_EQ(luminance(std::array<double, 3>{0.0, 1.0, 0.0}), 0.7152);
    EXPECT_DOUBLE_EQ(luminance(std::array<double, 3>{0.0, 0.0, 1.0}), 0.0722);
}

TEST(Luminance, GreyStaysGrey) {
    for (double v : {0.0, 1.0, -40.0, 3071.0, 1e30}) {
        EXPECT_NEAR(luminance(std::array<double, 3>{v, v, v}), v, 1e-12 * std::abs(v)) << v;
    }
}

TEST(Luminance, FloatPointerAndVec3sAgree) {
    const float rgb[3] = {10.0f, 20.0f, 30.0f};
    const double expected = 0.2126 * 10.0 + 0.7152 * 20.0 + 0.0722 * 30.0;
    EXPECT_NEAR(luminance(rgb), expected, 1e-9);
    EXPECT_NEAR(luminance(openvdb::Vec3s(10.0f, 20.0f, 30.0f)), expected, 1e-9);
}

TEST(Luminance, NaNInAnyChannelPropagates) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_TRUE(std::isnan(luminance(std::array<double, 3>{nan, 0.0, 0.0})));
    EXPECT_TRUE(std::isnan(luminance(std::array<double, 3>{0.0, 0.0, nan})));
}

}  // namespace
}  // namespace gvr
