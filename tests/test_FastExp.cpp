// The polynomial exp of the fit's kernel and the renderer: its stated accuracy on
// t <= 0, its floor below -87, and the same values in four and eight lanes.

#include "pipeline/FastExp.h"

#include <gtest/gtest.h>

#include <cmath>
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

template <typename Floats>
std::vector<float> expInLanes(const std::vector<float>& t) {
    constexpr int kLanes = sizeof(Floats) / sizeof(float);
    std::vector<float> out(t.size());
    for (std::size_t first = 0; first < t.size(); first += kLanes) {
        Floats in{};
        for (int i = 0; i < kLanes && first + i < t.size(); ++i) in[i] = t[first + i];
        const Floats e = expNonPositive(in);
        for (int i = 0; i < kLanes && first + i < t.size(); ++i) out[first + i] = e[i];
    }
    return out;
}

__attribute__((target("avx2,fma"))) std::vector<float> expInEightLanes(const std::vector<float>& t) {
    return expInLanes<Floats8>(t);
}

TEST(FastExp, IsWithinItsStatedErrorDownToMinus87) {
    const std::vector<float> t = nonPositiveArguments();
    const std::vector<float> e = expInLanes<Floats4>(t);
    double worst = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        const double exact = std::exp(double(t[k]));
        worst = std::max(worst, std::abs(e[k] - exact) / exact);
    }
    EXPECT_LT(worst, 3e-7) << "the header promises 3e-7 relative";
    EXPECT_EQ(expInLanes<Floats4>({0.0f})[0], 1.0f);
}

TEST(FastExp, BelowMinus87ItIsExpOfMinus87) {
    const float floor = expInLanes<Floats4>({-87.0f})[0];
    EXPECT_NEAR(floor, std::exp(-87.0), 3e-7 * std::exp(-87.0));
    for (float t : {-87.5f, -100.0f, -1e6f, -INFINITY}) EXPECT_EQ(expInLanes<Floats4>({t})[0], floor) << t;
}

TEST(FastExp, EightLanesWithFusedMultiplyAddsAgreeWithFour) {
    if (!processorHasAvx2Fma()) GTEST_SKIP() << "no AVX2 and FMA on this processor";
    const std::vector<float> t = nonPositiveArguments();
    const std::vector<float> four = expInLanes<Floats4>(t), eight = expInEightLanes(t);
    for (std::size_t k = 0; k < t.size(); ++k) {
        // The fused multiply-adds round once where four lanes round twice.
        EXPECT_NEAR(eight[k], four[k], 2e-7 * four[k]) << "t = " << t[k];
    }
}

}  // namespace
}  // namespace gvr
