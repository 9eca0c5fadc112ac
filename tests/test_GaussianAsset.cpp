// The asset as data: dropping the weakest Gaussians, and picking structures.

#include "pipeline/Error.h"
#include "pipeline/GaussianAsset.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

/// Three labelled Gaussians whose peak amplitudes are 0.5 * colour: 1.0, 0.25, 2.0.
GaussianAsset threeLabelled() {
    GaussianAsset asset;
    asset.params = GaussianParameters(3, 1);
    const float colours[3] = {2.0f, -0.5f, 4.0f};  // opacity logits 0: opacity 1/2
    for (std::size_t i = 0; i < 3; ++i) {
        asset.params.at(kMeans, i)[0] = float(i);
        *asset.params.at(kColours, i) = colours[i];
    }
    asset.labels = {4, 4, 9};
    asset.labelTable.names = {{4, "left"}, {9, "right"}};
    return asset;
}

TEST(GaussianAsset, KeepStrongestDropsTheSmallestPeaksAndKeepsOrderAndLabels) {
    GaussianAsset asset = threeLabelled();
    keepStrongest(asset, 2);
    ASSERT_EQ(asset.params.count(), 2u);
    EXPECT_EQ(asset.params.at(kMeans, 0)[0], 0.0f);
    EXPECT_EQ(asset.params.at(kMeans, 1)[0], 2.0f);
    EXPECT_EQ(asset.labels, (std::vector<int>{4, 9}));
}

TEST(GaussianAsset, SelectingStructuresKeepsTheirGaussiansAndNames) {
    const GaussianAsset asset = threeLabelled();
    const GaussianAsset right = selectStructures(asset, "right", "", "a.gvr");
    ASSERT_EQ(right.params.count(), 1u);
    EXPECT_EQ(right.params.at(kMeans, 0)[0], 2.0f);
    EXPECT_EQ(right.labelTable.names.size(), 1u);
    EXPECT_EQ(selectStructures(asset, "", "", "a.gvr").params.count(), 3u);  // nothing asked: all
    EXPECT_EQ(selectStructures(asset, "", "left", "a.gvr").params.count(), 1u);

    GaussianAsset unlabelled = asset;
    unlabelled.labels.clear();
    unlabelled.labelTable.names.clear();
    EXPECT_THROW(selectStructures(unlabelled, "left", "", "a.gvr"), InputError);
}

}  // namespace
}  // namespace gvr
