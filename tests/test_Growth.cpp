// Coarse to fine: the growth schedule, and splits that leave the field nearly as it was.

#include "Fitter.h"
#include "GaussianField.h"
#include "Growth.h"
#include "TestHelpers.h"
#include "VolumeError.h"

#include <cmath>

namespace gvr {
namespace {

TEST(Growth, EachStageBeforeTheLastHalvesTheCountRoundingUp) {
    EXPECT_EQ(countAtStage(100, 2, 0), 25u);
    EXPECT_EQ(countAtStage(101, 2, 0), 26u);
    EXPECT_EQ(countAtStage(101, 2, 1), 51u);
    EXPECT_EQ(countAtStage(101, 2, 2), 101u);
    EXPECT_EQ(countAtStage(3, 4, 0), 1u);  // never none while some are wanted
    EXPECT_EQ(countAtStage(0, 4, 0), 0u);
    EXPECT_EQ(countAtStage(100, 0, 0), 100u);
}

TEST(Growth, TheDoublingsAreSpreadOverTheShare) {
    EXPECT_EQ(stageAt(0.0, 2, 0.3), 0);
    EXPECT_EQ(stageAt(0.149, 2, 0.3), 0);
    EXPECT_EQ(stageAt(0.151, 2, 0.3), 1);
    EXPECT_EQ(stageAt(0.3, 2, 0.3), 2);
    EXPECT_EQ(stageAt(0.99, 2, 0.3), 2);
    EXPECT_EQ(stageAt(0.0, 0, 0.3), 0);
    EXPECT_EQ(stageAt(std::nan(""), 3, 0.3), 3);  // a broken clock ends the growth, not the fit
}

/// One tilted, elongated Gaussian of amplitude 2 at the middle of a 40^3 box.
GaussianParameters tiltedGaussian() {
    GaussianParameters params(1, 1);
    std::copy_n(std::array<float, 3>{20.3f, 19.6f, 20.1f}.data(), 3, params.at(kMeans, 0));
    std::copy_n(std::array<float, 4>{0.9f, 0.2f, -0.3f, 0.25f}.data(), 4, params.at(kRotations, 0));
    std::copy_n(std::array<float, 3>{std::log(1.5f), std::log(4.0f), std::log(2.0f)}.data(), 3, params.at(kLogScales, 0));
    *params.at(kOpacityLogits, 0) = 0.0f;  // opacity 1/2
    *params.at(kColours, 0) = 4.0f;
    return params;
}

struct FieldSummary {
    double mass = 0.0, peak = 0.0;
    std::array<double, 3> centroid{};
};

FieldSummary summarise(const GaussianParameters& params, std::vector<float>* values = nullptr) {
    const GaussianField field(params, 6.0f);
    FieldSummary summary;
    std::vector<std::uint32_t> hits;
    for (int i = 0; i < 40; ++i) {
        for (int j = 0; j < 40; ++j) {
            for (int k = 0; k < 40; ++k) {
                const float x[3] = {float(i), float(j), float(k)};
                float f = 0.0f;
                field.evaluate(x, &f, hits);
                summary.mass += f;
                summary.peak = std::max(summary.peak, double(f));
                for (int a = 0; a < 3; ++a) summary.centroid[a] += f * x[a];
                if (values) values->push_back(f);
            }
        }
    }
    for (double& c : summary.centroid) c /= summary.mass;
    return summary;
}

TEST(Growth, ASplitKeepsTheMassTheCentreAndTheShape) {
    GaussianParameters params = tiltedGaussian();
    std::vector<float> before, after;
    const FieldSummary parent = summarise(params, &before);
    Adam adam(params.count(), params.channels);
    ASSERT_EQ(splitWidest(params, adam, 5), 1u);  // no more than there are
    ASSERT_EQ(params.count(), 2u);
    const FieldSummary halves = summarise(params, &after);

    EXPECT_NEAR(halves.mass, parent.mass, 1e-3 * parent.mass);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(halves.centroid[a], parent.centroid[a], 1e-3);
    double worst = 0.0;
    for (std::size_t v = 0; v < before.size(); ++v) worst = std::max(worst, double(std::abs(after[v] - before[v])));
    EXPECT_LT(worst, 0.05 * parent.peak);
    // The halves lie apart along the widest axis (sigma 4), half a sigma each way.
    const float* m0 = params.at(kMeans, 0);
    const float* m1 = params.at(kMeans, 1);
    EXPECT_NEAR(std::hypot(m1[0] - m0[0], m1[1] - m0[1], m1[2] - m0[2]), 4.0, 1e-4);
}

TEST(Growth, TheWidestAreSplitFirstAndAdamKeepsStep) {
    GaussianParameters params(3, 1);
    for (std::size_t i = 0; i < 3; ++i) {
        params.at(kMeans, i)[0] = 10.0f * float(i);
        params.at(kRotations, i)[0] = 1.0f;
        *params.at(kColours, i) = 1.0f;
    }
    params.at(kLogScales, 1)[2] = 2.0f;  // the widest
    params.at(kLogScales, 2)[0] = 1.0f;
    Adam adam(params.count(), params.channels);
    ASSERT_EQ(splitWidest(params, adam, 1), 1u);
    ASSERT_EQ(params.count(), 4u);
    EXPECT_NEAR(params.at(kMeans, 3)[0], 10.0f, 1e-5);  // the copy of Gaussian 1
    EXPECT_GT(params.at(kMeans, 3)[2], 0.0f);
    EXPECT_LT(params.at(kMeans, 1)[2], 0.0f);
    GaussianParameters gradient(params.count(), params.channels);
    std::fill(gradient.values[kMeans].begin(), gradient.values[kMeans].end(), 1.0f);
    adam.step(params, gradient, {0.1, 0.1, 0.1, 0.1, 0.1});
    EXPECT_TRUE(params.allFinite());
    EXPECT_NEAR(params.at(kMeans, 3)[0], 9.9f, 1e-4);
}

float blobs(int i, int j, int k) {
    const float a = float((i - 10) * (i - 10) + (j - 12) * (j - 12) + (k - 8) * (k - 8));
    const float b = float((i - 22) * (i - 22) + (j - 8) * (j - 8) + (k - 14) * (k - 14));
    return 200.0f * std::exp(-a / 18.0f) + 120.0f * std::exp(-b / 8.0f);
}

TEST(Growth, AGrowingFitEndsWithTheFullCountAndLearns) {
    const VolumeTarget target(test::makeGrid({32, 24, 24}, blobs), "blobs");
    FitSettings settings;
    settings.gaussians = 400;
    settings.iterations = 400;
    settings.voxelBatch = 4096;
    settings.slicePixels = 1024;
    settings.heldOutVoxels = 2048;
    settings.pruneEvery = 0;
    settings.growthDoublings = 3;
    std::vector<std::size_t> counts;
    const GaussianParameters params = fitGaussians(target, settings, [&](const FitProgress& p) {
        if (counts.empty() || counts.back() != p.gaussians) counts.push_back(p.gaussians);
    });
    EXPECT_EQ(counts, (std::vector<std::size_t>{50, 100, 200, 400}));
    EXPECT_EQ(params.count(), 400u);
    EXPECT_GT(measureVolumeError(GaussianField(params, 3.0f), target).psnr, 35.0);
}

}  // namespace
}  // namespace gvr
