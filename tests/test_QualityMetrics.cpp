// The metrics on cases with known answers. Agreement with scikit-image is checked
// by metrics_vs_skimage.py.

#include "pipeline/Fitter.h"
#include "pipeline/QualityMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace gvr {
namespace {

/// A smooth volume with structure at several scales, in 0..1000.
FloatVolume smoothVolume(openvdb::Coord dims, int channels = 1) {
    FloatVolume v(dims, channels);
    for (int k = 0; k < dims.z(); ++k) {
        for (int j = 0; j < dims.y(); ++j) {
            for (int i = 0; i < dims.x(); ++i) {
                for (int c = 0; c < channels; ++c) {
                    v.at(i, j, k)[c] = float(500 + 300 * std::sin(0.21 * i + c) * std::cos(0.13 * j) +
                                             150 * std::sin(0.4 * k + 0.05 * i * j / (1 + k)));
                }
            }
        }
    }
    return v;
}

FloatVolume withNoise(const FloatVolume& v, double sigma, unsigned seed) {
    FloatVolume out = v;
    std::mt19937 random(seed);
    std::normal_distribution<double> noise(0.0, sigma);
    for (float& x : out.values) x = float(x + noise(random));
    return out;
}

TEST(QualityMetrics, IdenticalInputsArePerfect) {
    const FloatVolume v = smoothVolume({40, 36, 30});
    SsimSettings settings;
    settings.dataRange = 1000.0;
    EXPECT_EQ(meanSquaredError(v, v), 0.0);
    EXPECT_TRUE(std::isinf(psnrFromMse(meanSquaredError(v, v), 1000.0)));
    EXPECT_NEAR(ssim(v, v, settings), 1.0, 1e-12);
    EXPECT_NEAR(msSsim(v, v, settings).value, 1.0, 1e-12);
}

TEST(QualityMetrics, ConstantOffsetGivesExactMse) {
    const FloatVolume v = smoothVolume({20, 18, 16}, 3);
    FloatVolume shifted = v;
    for (float& x : shifted.values) x += 2.5f;
    EXPECT_NEAR(meanSquaredError(v, shifted), 6.25, 1e-4);
    // A mask restricts the average to its voxels.
    std::vector<std::uint8_t> mask(v.voxelCount(), 0);
    FloatVolume partly = v;
    for (std::size_t n = 0; n < mask.size(); n += 3) {
        mask[n] = 1;
        for (int c = 0; c < 3; ++c) partly.values[n * 3 + c] += 4.0f;
    }
    EXPECT_NEAR(meanSquaredError(v, partly, mask), 16.0, 1e-3);
}

TEST(QualityMetrics, MaxErrorIsTheLargestOverChannelsAndTheMask) {
    const FloatVolume v = smoothVolume({20, 18, 16}, 3);
    FloatVolume off = v;
    off.values[7 * 3 + 2] -= 9.0f;  // voxel 7's last channel
    off.values[8 * 3 + 0] += 3.0f;
    EXPECT_NEAR(maxAbsoluteError(v, off), 9.0, 1e-5);
    std::vector<std::uint8_t> mask(v.voxelCount(), 1);
    mask[7] = 0;
    EXPECT_NEAR(maxAbsoluteError(v, off, mask), 3.0, 1e-5);
    EXPECT_EQ(maxAbsoluteError(v, v), 0.0);
}

TEST(QualityMetrics, GaussianNoiseGivesTheExpectedPsnr) {
    const FloatVolume v = smoothVolume({64, 64, 48});
    const double peak = 1000.0;
    for (double sigma : {1.0, 10.0, 50.0}) {
        const double psnr = psnrFromMse(meanSquaredError(v, withNoise(v, sigma, 11)), peak);
        EXPECT_NEAR(psnr, 20.0 * std::log10(peak / sigma), 0.1) << "sigma " << sigma;
    }
}

TEST(QualityMetrics, SsimFallsWithNoiseAndIsSymmetric) {
    const FloatVolume v = smoothVolume({48, 48, 24});
    SsimSettings settings;
    settings.dataRange = 1000.0;
    const FloatVolume slightly = withNoise(v, 5.0, 1), badly = withNoise(v, 80.0, 2);
    const double good = ssim(v, slightly, settings), bad = ssim(v, badly, settings);
    EXPECT_GT(good, bad);
    EXPECT_LT(good, 1.0);
    EXPECT_GT(bad, 0.0);
    EXPECT_NEAR(ssim(slightly, v, settings), good, 1e-12);
}

TEST(QualityMetrics, ScalesFallBackForSmallVolumes) {
    SsimSettings settings;
    EXPECT_EQ(msSsimScales({181, 217, 181}, settings), 5);
    EXPECT_EQ(msSsimScales({256, 240, 1}, settings), 5);   // an image: z is not smoothed
    EXPECT_EQ(msSsimScales({64, 64, 1}, settings), 3);     // 64 -> 32 -> 16 (-> 8 < 11)
    EXPECT_EQ(msSsimScales({256, 286, 15}, settings), 1);  // 15 slices: only the first scale
    EXPECT_EQ(msSsimScales({8, 8, 8}, settings), 1);       // nothing to smooth at all
    const FloatVolume v = smoothVolume({64, 64, 1});
    settings.dataRange = 1000.0;
    const MsSsim small = msSsim(v, withNoise(v, 20.0, 3), settings);
    EXPECT_EQ(small.scales, 3);
    EXPECT_GT(small.value, 0.0);
    EXPECT_LT(small.value, 1.0);
}

TEST(QualityMetrics, TinyVolumesStillGiveFiniteValues) {
    const FloatVolume v = smoothVolume({5, 4, 3});
    SsimSettings settings;
    settings.dataRange = 1000.0;
    const FloatVolume noisy = withNoise(v, 30.0, 4);
    EXPECT_TRUE(std::isfinite(ssim(v, noisy, settings)));
    EXPECT_TRUE(std::isfinite(msSsim(v, noisy, settings).value));
}

TEST(QualityMetrics, ResamplingOntoTheSameLatticeIsExact) {
    FloatVolume v = smoothVolume({12, 10, 8});
    v.worldFromIndex.setToScale(openvdb::Vec3d(0.5, 0.5, 2.0));
    const FloatVolume same = resampleTrilinear(v, v.dims, v.worldFromIndex);
    EXPECT_EQ(meanSquaredError(v, same), 0.0);
    // Half-voxel shifts along x average neighbours.
    openvdb::math::Mat4d shifted = v.worldFromIndex;
    shifted.setTranslation(openvdb::Vec3d(0.25, 0.0, 0.0));
    const FloatVolume half = resampleTrilinear(v, v.dims, shifted);
    EXPECT_NEAR(half.at(3, 4, 5)[0], 0.5f * (v.at(3, 4, 5)[0] + v.at(4, 4, 5)[0]), 1e-3);
}

}  // namespace
}  // namespace gvr

namespace gvr {
namespace {

FloatVolume rgbaImage(const std::vector<std::array<float, 4>>& pixels) {
    FloatVolume image(openvdb::Coord(int(pixels.size()), 1, 1), 4);
    for (std::size_t p = 0; p < pixels.size(); ++p)
        std::copy(pixels[p].begin(), pixels[p].end(), image.values.begin() + 4 * p);
    return image;
}

TEST(RenderingError, CountsOnlyCoveredPixelsAsSeenOverBlackAndWhite) {
    // Pixel 0: shared transparent background. Pixel 1: the same grey, half as opaque
    // in the test. Pixel 2: covered by the reference only.
    const FloatVolume reference = rgbaImage({{0, 0, 0, 0}, {0.4f, 0.4f, 0.4f, 0.8f}, {0.2f, 0.1f, 0.0f, 0.5f}});
    const FloatVolume test = rgbaImage({{0, 0, 0, 0}, {0.2f, 0.2f, 0.2f, 0.4f}, {0, 0, 0, 0}});
    const RenderingError error = renderingError(reference, test);
    EXPECT_EQ(error.coveredPixels, 2u);
    // Over black the differences are the premultiplied colours; over white each
    // gains the difference in (1 - alpha): 0.2 - 0.4 and 0.2 - 0.5, 0.1 - 0.5, 0 - 0.5.
    EXPECT_NEAR(error.overBlack, (3 * 0.04 + 0.04 + 0.01 + 0.0) / 6.0, 1e-6);
    EXPECT_NEAR(error.overWhite, (3 * 0.04 + 0.09 + 0.16 + 0.25) / 6.0, 1e-6);
    EXPECT_EQ(renderingError(reference, reference).overWhite, 0.0);
    EXPECT_EQ(renderingError(test, test).coveredPixels, 1u);
    EXPECT_THROW(renderingError(FloatVolume(openvdb::Coord(2, 1, 1), 3), FloatVolume(openvdb::Coord(2, 1, 1), 3)),
                 std::invalid_argument);
}

TEST(RenderingDifference, ShowsPerPixelTheErrorThatRenderingErrorAverages) {
    const FloatVolume reference = rgbaImage({{0, 0, 0, 0}, {0.4f, 0.4f, 0.4f, 0.8f}, {0.2f, 0.1f, 0.0f, 0.5f}});
    const FloatVolume test = rgbaImage({{0, 0, 0, 0}, {0.2f, 0.2f, 0.2f, 0.4f}, {0, 0, 0, 0}});
    const float gain = 4.0f;
    const FloatVolume difference = renderingDifference(reference, test, gain);
    ASSERT_EQ(difference.dims, reference.dims);
    // Pixel 0: covered by neither, black. Pixel 1, red: 0.2 over black, 0.2 - 0.4 over white.
    EXPECT_EQ(difference.values[0], 0.0f);
    EXPECT_NEAR(difference.values[4], gain * std::sqrt(0.5 * (0.04 + 0.04)), 1e-6);
    for (std::size_t p = 0; p < 3; ++p) EXPECT_EQ(difference.values[4 * p + 3], 1.0f) << "opaque";
    // Over the covered pixels, the mean square is the two errors' mean.
    const RenderingError error = renderingError(reference, test);
    double sum = 0.0;
    for (std::size_t p = 1; p < 3; ++p) {
        for (int c = 0; c < 3; ++c) sum += std::pow(difference.values[4 * p + c] / gain, 2.0);
    }
    EXPECT_NEAR(sum / (3.0 * error.coveredPixels), 0.5 * (error.overBlack + error.overWhite), 1e-6);
    EXPECT_THROW(
        renderingDifference(FloatVolume(openvdb::Coord(2, 1, 1), 3), FloatVolume(openvdb::Coord(2, 1, 1), 3), gain),
        std::invalid_argument);
}

}  // namespace
}  // namespace gvr
