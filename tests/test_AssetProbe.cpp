// Probing an asset's field: the Gaussians' sum, mapped to physical units by the
// asset's offset and scale, with the count of Gaussians that reach the point.

#include "pipeline/AssetProbe.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace gvr {
namespace {

/// Unit-sigma Gaussians at (5, 5, 5), each of amplitude 1 per channel (opacity 1/2,
/// colour 2), mapped to physical = offset + 500 * normalised.
GaussianAsset asset(std::size_t count, int channels) {
    GaussianAsset a;
    a.params = GaussianParameters(count, channels);
    for (std::size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) a.params.at(kMeans, i)[k] = 5.0f;
        a.params.at(kRotations, i)[0] = 1.0f;
        for (int c = 0; c < channels; ++c) a.params.at(kColours, i)[c] = 2.0f;
    }
    a.cutoffSigmas = 3.0f;
    a.mapping.offset = {-1000.0, 10.0, 20.0};
    a.mapping.scale = 500.0;
    return a;
}

TEST(AssetProbe, AtTheMeanGivesThePeak) {
    AssetProbe probe(asset(1, 1));
    EXPECT_EQ(probe.channels(), 1);
    const AssetProbe::Sample sample = probe.at({5.0, 5.0, 5.0});
    EXPECT_DOUBLE_EQ(sample.value[0], -1000.0 + 500.0);
    EXPECT_EQ(sample.gaussians, 1u);
    EXPECT_EQ(sample.value[1], 0.0);  // unused channels stay zero
}

TEST(AssetProbe, FractionalIndicesFollowTheGaussian) {
    AssetProbe probe(asset(1, 1));
    EXPECT_NEAR(probe.at({6.0, 5.0, 5.0}).value[0], -1000.0 + 500.0 * std::exp(-0.5), 1e-3);
    EXPECT_NEAR(probe.at({5.5, 5.0, 4.5}).value[0], -1000.0 + 500.0 * std::exp(-0.25), 1e-3);
}

TEST(AssetProbe, FarAwayGivesTheBackground) {
    AssetProbe probe(asset(1, 1));
    const AssetProbe::Sample sample = probe.at({50.0, -40.0, 5.0});
    EXPECT_EQ(sample.value[0], -1000.0);
    EXPECT_EQ(sample.gaussians, 0u);
}

TEST(AssetProbe, OverlappingGaussiansAddUp) {
    AssetProbe probe(asset(2, 1));
    const AssetProbe::Sample sample = probe.at({5.0, 5.0, 5.0});
    EXPECT_DOUBLE_EQ(sample.value[0], -1000.0 + 2 * 500.0);
    EXPECT_EQ(sample.gaussians, 2u);
}

TEST(AssetProbe, EachColourChannelHasItsOwnOffset) {
    AssetProbe probe(asset(1, 3));
    EXPECT_EQ(probe.channels(), 3);
    const AssetProbe::Sample sample = probe.at({5.0, 5.0, 5.0});
    EXPECT_DOUBLE_EQ(sample.value[0], -500.0);
    EXPECT_DOUBLE_EQ(sample.value[1], 510.0);
    EXPECT_DOUBLE_EQ(sample.value[2], 520.0);
}

TEST(AssetProbe, RepeatedProbesDoNotAccumulate) {
    // The probe reuses its scratch list of hits; a second call must start afresh.
    AssetProbe probe(asset(1, 1));
    probe.at({5.0, 5.0, 5.0});
    const AssetProbe::Sample far = probe.at({50.0, 50.0, 50.0});
    EXPECT_EQ(far.gaussians, 0u);
    const AssetProbe::Sample near = probe.at({5.0, 5.0, 5.0});
    EXPECT_EQ(near.gaussians, 1u);
    EXPECT_DOUBLE_EQ(near.value[0], -500.0);
}

}  // namespace
}  // namespace gvr
