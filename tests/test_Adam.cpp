// Adam against steps worked out by hand: the bias-corrected first step, a second
// step, a non-finite gradient that leaves its Gaussian alone, and moments that
// follow their Gaussians through permute, keepOnly and grow.

#include "pipeline/Adam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace gvr;

namespace {

constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEpsilon = 1e-12;

/// One parameter's step, in double: the moments carried in @a m and @a v.
double handStep(double gradient, int step, double rate, double& m, double& v) {
    m = kBeta1 * m + (1 - kBeta1) * gradient;
    v = kBeta2 * v + (1 - kBeta2) * gradient * gradient;
    const double mHat = m / (1 - std::pow(kBeta1, step)), vHat = v / (1 - std::pow(kBeta2, step));
    return -rate * mHat / (std::sqrt(vHat) + kEpsilon);
}

std::array<double, kGroupCount> rates() { return {0.1, 0.2, 0.3, 0.4, 0.5}; }

void step(Adam& adam, GaussianParameters& params, const GaussianParameters& gradient,
          std::vector<std::uint8_t>& updated) {
    adam.beginStep(rates());
    updated.assign(params.count(), 0);
    adam.update(params, gradient, 0, params.count(), updated.data());
}

}  // namespace

TEST(Adam, TwoStepsMatchTheHandWorkedUpdateInEveryGroup) {
    GaussianParameters params(2, 3), gradient(2, 3);
    Adam adam(2, 3);
    std::vector<std::uint8_t> updated;
    std::vector<double> m[kGroupCount], v[kGroupCount], expected[kGroupCount];
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t n = params.values[g].size();
        m[g].assign(n, 0.0);
        v[g].assign(n, 0.0);
        expected[g].assign(n, 0.0);
    }
    for (int s = 1; s <= 2; ++s) {
        for (int g = 0; g < kGroupCount; ++g) {
            for (std::size_t k = 0; k < gradient.values[g].size(); ++k) {
                // Signs and sizes that differ by group, parameter and step.
                const double value = (k % 2 ? -1.0 : 1.0) * (0.5 + 0.25 * double(k)) * (s == 1 ? 1.0 : -3.0 + g);
                gradient.values[g][k] = float(value);
                expected[g][k] += handStep(value, s, rates()[g], m[g][k], v[g][k]);
            }
        }
        step(adam, params, gradient, updated);
        EXPECT_EQ(updated, (std::vector<std::uint8_t>{1, 1}));
        for (int g = 0; g < kGroupCount; ++g) {
            for (std::size_t k = 0; k < params.values[g].size(); ++k) {
                EXPECT_NEAR(params.values[g][k], expected[g][k], 1e-5 * (1 + std::abs(expected[g][k])))
                    << "step " << s << ", group " << g << ", value " << k;
            }
        }
    }
    // The first step of Adam moves every parameter by its rate, whatever the gradient's size.
    GaussianParameters fresh(1, 1), scaled(1, 1);
    Adam once(1, 1);
    scaled.values[kColours][0] = 1e-6f;
    std::vector<std::uint8_t> flag;
    step(once, fresh, scaled, flag);
    EXPECT_NEAR(fresh.values[kColours][0], -0.5, 1e-5);
}

TEST(Adam, ANonFiniteGradientLeavesItsGaussianAndItsMomentsAlone) {
    GaussianParameters params(3, 1), gradient(3, 1);
    for (int g = 0; g < kGroupCount; ++g) std::fill(gradient.values[g].begin(), gradient.values[g].end(), 1.0f);
    gradient.at(kLogScales, 1)[2] = NAN;
    Adam adam(3, 1);
    std::vector<std::uint8_t> updated;
    step(adam, params, gradient, updated);
    EXPECT_EQ(updated, (std::vector<std::uint8_t>{1, 0, 1}));
    for (int g = 0; g < kGroupCount; ++g) {
        for (int k = 0; k < params.width(ParameterGroup(g)); ++k) EXPECT_EQ(params.at(ParameterGroup(g), 1)[k], 0.0f);
        EXPECT_NEAR(params.at(ParameterGroup(g), 0)[0], -rates()[g], 1e-5);
    }
    // A zero gradient next: Gaussian 1 has no momentum to carry, the others do.
    for (int g = 0; g < kGroupCount; ++g) std::fill(gradient.values[g].begin(), gradient.values[g].end(), 0.0f);
    step(adam, params, gradient, updated);
    EXPECT_EQ(*params.at(kColours, 1), 0.0f);
    EXPECT_LT(*params.at(kColours, 0), -rates()[kColours]);
}

TEST(Adam, MomentsFollowTheirGaussiansThroughPermuteKeepOnlyAndGrow) {
    GaussianParameters params(3, 1), gradient(3, 1);
    for (std::size_t i = 0; i < 3; ++i) *gradient.at(kColours, i) = float(i + 1) * (i == 1 ? -1.0f : 1.0f);
    Adam adam(3, 1);
    std::vector<std::uint8_t> updated;
    step(adam, params, gradient, updated);
    // Momentum alone moves each colour on in the direction of its own first gradient.
    params.permute({2, 0, 1});
    adam.permute({2, 0, 1});
    params.keepOnly({true, false, true});  // keeps old Gaussians 2 and 1
    adam.keepOnly({true, false, true});
    params.append(GaussianParameters(1, 1));
    adam.grow(3);
    const std::vector<float> before = params.values[kColours];
    std::fill(gradient.values[kColours].begin(), gradient.values[kColours].end(), 0.0f);
    step(adam, params, gradient, updated);
    const auto moved = [&](std::size_t i) { return params.values[kColours][i] - before[i]; };
    double m = 0, v = 0;
    handStep(1.0, 1, 0.5, m, v);
    const double carried = handStep(0.0, 2, 0.5, m, v);  // the same for any first gradient: m / sqrt(v) keeps its size
    EXPECT_NEAR(moved(0), carried, 1e-5);                // old Gaussian 2, first gradient +3
    EXPECT_NEAR(moved(1), -carried, 1e-5);               // old Gaussian 1, first gradient -2
    EXPECT_EQ(moved(2), 0.0f);                           // grown: zero moments
}
