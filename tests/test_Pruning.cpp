// Pruning and respawn: negligible Gaussians go with their Adam moments, survivors
// keep their order, and the freed places go to the sites of largest residual.

#include "pipeline/Adam.h"
#include "pipeline/GaussianKernel.h"
#include "pipeline/Pruning.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace gvr;

namespace {

/// Four Gaussians of peak amplitude 0.5 * colour, marked by their x position.
GaussianParameters fourGaussians(const std::array<float, 4>& colours) {
    GaussianParameters params(4, 1);
    for (std::size_t i = 0; i < 4; ++i) {
        params.at(kMeans, i)[0] = float(10 * i);
        params.at(kRotations, i)[0] = 1.0f;
        *params.at(kColours, i) = colours[i];  // opacity logit 0: opacity 1/2
    }
    return params;
}

}  // namespace

TEST(Pruning, NegligibleGaussiansGoAndSitesTakeTheirPlaces) {
    GaussianParameters params = fourGaussians({1.0f, 0.001f, -0.8f, 0.0001f});
    Adam adam(4, 1);
    const std::vector<RespawnSite> sites = {
        {{1.f, 2.f, 3.f}, {0.3f, 0.f, 0.f}}, {{4.f, 5.f, 6.f}, {-0.1f, 0.f, 0.f}}, {{7.f, 8.f, 9.f}, {0.9f, 0.f, 0.f}}};
    const PruneResult result = pruneAndRespawn(params, adam, 0.01, sites);
    EXPECT_EQ(result.removed, 2u);
    EXPECT_EQ(result.respawned, 2u) << "no more than were negligible";
    ASSERT_EQ(params.count(), 4u);
    // Survivors first, in their order (x = 0 and 20); a negative colour is not negligible.
    EXPECT_EQ(params.at(kMeans, 0)[0], 0.0f);
    EXPECT_EQ(params.at(kMeans, 1)[0], 20.0f);
    EXPECT_EQ(*params.at(kColours, 1), -0.8f);
    // New Gaussians at the first sites, opacity 1/2, colour filling the residual.
    for (std::size_t s = 0; s < 2; ++s) {
        const std::size_t i = 2 + s;
        for (int a = 0; a < 3; ++a) EXPECT_EQ(params.at(kMeans, i)[a], sites[s].position[a]);
        EXPECT_EQ(*params.at(kOpacityLogits, i), 0.0f);
        EXPECT_NEAR(peakAmplitude(params, i), std::abs(sites[s].residual[0]), 1e-6);
        EXPECT_EQ(params.at(kRotations, i)[0], 1.0f);
    }
}

TEST(Pruning, AdamMomentsFollowTheSurvivorsAndStartAtZeroForNewcomers) {
    GaussianParameters params = fourGaussians({1.0f, 0.001f, 0.8f, 0.5f});
    Adam adam(4, 1);
    GaussianParameters gradient(4, 1);
    for (std::size_t i = 0; i < 4; ++i) *gradient.at(kColours, i) = i % 2 ? -1.0f : 1.0f;
    std::vector<std::uint8_t> updated(4);
    adam.beginStep({0, 0, 0, 0, 0.01});
    adam.update(params, gradient, 0, 4, updated.data());
    const std::vector<RespawnSite> sites = {{{0.f, 0.f, 0.f}, {0.2f, 0.f, 0.f}}};
    ASSERT_EQ(pruneAndRespawn(params, adam, 0.01, sites).removed, 1u);  // Gaussian 1
    const std::vector<float> before = params.values[kColours];
    std::fill(gradient.values[kColours].begin(), gradient.values[kColours].end(), 0.0f);
    adam.beginStep({0, 0, 0, 0, 0.01});
    adam.update(params, gradient, 0, 4, updated.data());
    // Old Gaussians 0 and 2 (gradient +1) keep moving down, old 3 (gradient -1) up,
    // each with its own moments; the newcomer has none.
    EXPECT_LT(params.values[kColours][0], before[0]);
    EXPECT_LT(params.values[kColours][1], before[1]);
    EXPECT_GT(params.values[kColours][2], before[2]);
    EXPECT_EQ(params.values[kColours][3], before[3]);
}

TEST(Pruning, WithFewerSitesThanNegligibleGaussiansTheWeakestMoveAndTheCountStays) {
    GaussianParameters params = fourGaussians({0.004f, 1.0f, 0.0002f, 0.001f});
    Adam adam(4, 1);
    EXPECT_EQ(negligibleCount(params, 0.01), 3u);
    const PruneResult result =
        pruneAndRespawn(params, adam, 0.01, {{{5.f, 5.f, 5.f}, {0.4f, 0.f, 0.f}}, {{6.f, 6.f, 6.f}, {0.2f, 0.f, 0.f}}});
    EXPECT_EQ(result.removed, 2u);
    EXPECT_EQ(result.respawned, 2u);
    ASSERT_EQ(params.count(), 4u);
    // Peaks 0.0001 (x = 20) and 0.0005 (x = 30) go; 0.002 (x = 0) stays, before 0.5 (x = 10).
    EXPECT_EQ(params.at(kMeans, 0)[0], 0.0f);
    EXPECT_EQ(params.at(kMeans, 1)[0], 10.0f);
    EXPECT_EQ(params.at(kMeans, 2)[0], 5.0f);
    EXPECT_EQ(params.at(kMeans, 3)[0], 6.0f);
}

TEST(Pruning, NothingBelowTheThresholdChangesNothing) {
    GaussianParameters params = fourGaussians({1.0f, 0.5f, -0.8f, 0.3f});
    const GaussianParameters original = params;
    Adam adam(4, 1);
    const PruneResult result = pruneAndRespawn(params, adam, 0.01, {{{1.f, 1.f, 1.f}, {1.f, 0.f, 0.f}}});
    EXPECT_EQ(result.removed, 0u);
    EXPECT_EQ(result.respawned, 0u);
    for (int g = 0; g < kGroupCount; ++g) EXPECT_EQ(params.values[g], original.values[g]);
}
