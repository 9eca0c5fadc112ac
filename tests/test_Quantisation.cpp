// The shared quantisation of both asset bodies.

#include "io/asset/Quantisation.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace gvr;

TEST(Quantisation, LevelsRoundTripWithinHalfAStepAndClampAtTheEnds) {
    for (const int bits : {4, 10, 16}) {
        const float lo = -3.0f, hi = 5.0f;
        const double step = (hi - lo) / double((1u << bits) - 1u);
        for (float x = lo; x <= hi; x += 0.37f) {
            EXPECT_LE(std::abs(dequantise(quantise(x, lo, hi, bits), lo, hi, bits) - x), 0.5 * step + 1e-6) << bits;
        }
        EXPECT_EQ(quantise(lo - 10.0f, lo, hi, bits), 0u);
        EXPECT_EQ(quantise(hi + 10.0f, lo, hi, bits), (1u << bits) - 1u);
        EXPECT_EQ(dequantise(0, lo, hi, bits), lo);
        EXPECT_EQ(dequantise((1u << bits) - 1u, lo, hi, bits), hi);
    }
    EXPECT_EQ(quantise(1.0f, 2.0f, 2.0f, 8), 0u) << "an empty range has one level";
}

TEST(Quantisation, TheLargestQuaternionComponentIsRecoveredFromTheOtherThree) {
    const float raw[4] = {0.2f, -0.5f, 0.7f, 0.3f};
    const float norm = std::sqrt(0.04f + 0.25f + 0.49f + 0.09f);
    float q[4];
    for (int k = 0; k < 4; ++k) q[k] = raw[k] / norm;
    const float largest = q[2];
    q[2] = -99.0f;
    completeQuaternion(2, q);
    EXPECT_NEAR(q[2], largest, 1e-6);
    // Rounding can push the other three past unit length: the largest becomes 0, never NaN.
    float over[4] = {0.8f, 0.6f, 0.1f, -1.0f};
    completeQuaternion(3, over);
    EXPECT_EQ(over[3], 0.0f);
}
