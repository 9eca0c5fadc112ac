// The piecewise-linear transfer function: interpolation, clamping and its transparent range.

#include "pipeline/TransferFunction.h"

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
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0}}, {20, {1, 1, 1, 0}}, {30, {1, 1, 1, 1}}}, "t").transparentUpTo(),
              20.0);
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0.1f}}, {30, {1, 1, 1, 1}}}, "t").transparentUpTo(), -INFINITY);
    EXPECT_EQ(TransferFunction({{10, {0, 0, 0, 0}}, {30, {1, 1, 1, 0}}}, "t").transparentUpTo(), INFINITY);
}

}  // namespace
}  // namespace gvr
