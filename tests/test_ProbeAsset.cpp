// What gvr probe and asset.probe report: the Gaussians' field, or with the residual
// layer the bounded reconstruction, exact to the bound at voxel centres.

#include "tests/TestHelpers.h"
#include "workflow/ComparisonInput.h"
#include "workflow/ProbeAsset.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

openvdb::GridBase::Ptr ridgedBall() {
    return test::makeGrid({12, 10, 14}, [](int i, int j, int k) {
        const double r2 = (i - 6.0) * (i - 6.0) + (j - 5.0) * (j - 5.0) + (k - 7.0) * (k - 7.0);
        return float(-50.0 + 120.0 * std::exp(-r2 / 10.0) + ((i + j + k) % 3));
    });
}

TEST(ProbeAsset, TheLayerHoldsItsBoundAtVoxelCentresAndTheGaussiansDoNot) {
    const openvdb::GridBase::Ptr grid = ridgedBall();
    const GaussianAsset asset = test::boundedAsset(grid, 5, 0.1);
    const FloatVolume source = comparisonInputOf(grid, "grid").volume;
    std::vector<std::array<double, 3>> centres;
    for (int k = 0; k < 14; k += 3) {
        for (int j = 0; j < 10; j += 2) {
            for (int i = 0; i < 12; ++i) centres.push_back({double(i), double(j), double(k)});
        }
    }
    const auto bounded = probeAsset(asset, centres, AssetLayers::All, "asset");
    const auto preview = probeAsset(asset, centres, AssetLayers::Gaussians, "asset");
    double previewWorst = 0.0;
    for (std::size_t n = 0; n < centres.size(); ++n) {
        const auto& c = centres[n];
        const double truth = *source.at(int(c[0]), int(c[1]), int(c[2]));
        EXPECT_LE(std::abs(bounded[n].value[0] - truth), 0.1) << c[0] << "," << c[1] << "," << c[2];
        EXPECT_EQ(bounded[n].gaussians, preview[n].gaussians);
        previewWorst = std::max(previewWorst, std::abs(preview[n].value[0] - truth));
    }
    EXPECT_GT(previewWorst, 1.0);  // five Gaussians in three iterations are no copy
}

TEST(ProbeAsset, BetweenVoxelsTheLayerIsTrilinearAndBeyondThemTheBackground) {
    const GaussianAsset asset = test::boundedAsset(ridgedBall(), 5, 0.1);
    const auto at = [&](double i, double j, double k) {
        return probeAsset(asset, {{i, j, k}}, AssetLayers::All, "asset").front().value[0];
    };
    EXPECT_NEAR(at(3.5, 4.0, 6.0), 0.5 * (at(3.0, 4.0, 6.0) + at(4.0, 4.0, 6.0)), 1e-4);
    EXPECT_DOUBLE_EQ(at(-5.0, 2.0, 2.0), asset.source.background);
    EXPECT_DOUBLE_EQ(at(1e300, 2.0, 2.0), asset.source.background);  // no int overflow on the way
    EXPECT_NEAR(at(-0.5, 2.0, 2.0), 0.5 * (at(0.0, 2.0, 2.0) + asset.source.background), 1e-4);
}

}  // namespace
}  // namespace gvr
