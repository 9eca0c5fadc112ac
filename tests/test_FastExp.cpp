// The polynomial exp of the fit's kernel and the renderer: its stated accuracy on
// t <= 0, its floor below -87, and the same values in four and eight lanes.

// GCC and clang note that passing eight floats by value without AVX would change
// the ABI. Every function here that passes them is inlined into one compiled with
// AVX2 (or handles four floats), so no such value crosses a call.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "pipeline/FastExp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace gvr {
namespace {

/// t from 0 down to -87 in small steps, with the values where the reduction's
/// integer n changes (multiples of ln 2) and their neighbours.
std::vector<float> nonPositiveArguments() {
    std::vector<float> t;
    for (float x = 0.0f; x >= -87.0f; x -= 0.0137f) t.push_back(x);
    for (int n = 0; n <= 125; ++n) {
        const float atMultiple = -float(n) * 0.69314718f;
        t.insert(t.end(), {atMultiple, std::nextafter(atMultiple, 0.0f), std::nextafter(atMultiple, -100.0f)});
    }
    return t;
}

/// expNonPositive over @a t, kLanes values at a time: @a expOfLanes(in, out) takes
/// and gives kLanes floats.
template <int kLanes, typename ExpOfLanes>
std::vector<float> inLanes(const std::vector<float>& t, ExpOfLanes expOfLanes) {
    std::vector<float> out(t.size());
    for (std::size_t first = 0; first < t.size(); first += kLanes) {
        float in[kLanes] = {}, e[kLanes];
        for (int i = 0; i < kLanes && first + i < t.size(); ++i) in[i] = t[first + i];
        expOfLanes(in, e);
        for (int i = 0; i < kLanes && first + i < t.size(); ++i) out[first + i] = e[i];
    }
    return out;
}

/// One call of expNonPositive on kLanes floats. Vectors pass only between inlined
/// functions without a target of their own, as in the fit's kernel: clang refuses
/// an AVX vector argument between a function compiled for AVX and one that is not.
template <typename Floats>
__attribute__((always_inline)) inline void expOfLanes(const float* in, float* out) {
    Floats t;
    std::memcpy(&t, in, sizeof t);
    const Floats e = expNonPositive(t);
    std::memcpy(out, &e, sizeof e);
}

void expOfFourLanes(const float* in, float* out) { expOfLanes<Floats4>(in, out); }

/// Compiled as the fit's eight-lane kernel is: AVX2 with fused multiply-adds.
__attribute__((target("avx2,fma"))) void expOfEightLanes(const float* in, float* out) { expOfLanes<Floats8>(in, out); }

std::vector<float> expInLanes(const std::vector<float>& t) { return inLanes<4>(t, expOfFourLanes); }

TEST(FastExp, IsWithinItsStatedErrorDownToMinus87) {
    const std::vector<float> t = nonPositiveArguments();
    const std::vector<float> e = expInLanes(t);
    double worst = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        const double exact = std::exp(double(t[k]));
        worst = std::max(worst, std::abs(e[k] - exact) / exact);
    }
    EXPECT_LT(worst, 3e-7) << "the header promises 3e-7 relative";
    EXPECT_EQ(expInLanes({0.0f})[0], 1.0f);
}

TEST(FastExp, BelowMinus87ItIsExpOfMinus87) {
    const float floor = expInLanes({-87.0f})[0];
    EXPECT_NEAR(floor, std::exp(-87.0), 3e-7 * std::exp(-87.0));
    for (float t : {-87.5f, -100.0f, -1e6f, -INFINITY}) EXPECT_EQ(expInLanes({t})[0], floor) << t;
}

TEST(FastExp, EightLanesWithFusedMultiplyAddsAgreeWithFour) {
    if (!processorHasAvx2Fma()) GTEST_SKIP() << "no AVX2 and FMA on this processor";
    const std::vector<float> t = nonPositiveArguments();
    const std::vector<float> four = expInLanes(t), eight = inLanes<8>(t, expOfEightLanes);
    for (std::size_t k = 0; k < t.size(); ++k) {
        // The fused multiply-adds round once where four lanes round twice.
        EXPECT_NEAR(eight[k], four[k], 2e-7 * four[k]) << "t = " << t[k];
    }
}

}  // namespace
}  // namespace gvr
