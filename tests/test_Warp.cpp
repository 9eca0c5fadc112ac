// The warp: an image pixel sees the intermediate image's light wherever its taps
// reach it, whichever rows compositing reached; its taps keep detail between
// texels, and its pixels stay valid premultiplied colour.
#include "render/Warp.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace gvr {
namespace {

/// A 40 x 36 intermediate image, dark but for one texel, with every row marked reached.
IntermediateImage oneTexel(int x, int y) {
    IntermediateImage image;
    image.width = 40;
    image.height = 36;
    image.rgba.assign(std::size_t(image.width) * image.height * 4, 0.0f);
    float* texel = image.rgba.data() + (std::size_t(y) * image.width + x) * 4;
    for (int c = 0; c < 4; ++c) texel[c] = 0.1f * (c + 1);
    image.reached.assign(image.height, PixelSpan{0, image.width - 1});
    return image;
}

/// Image pixels @a step intermediate pixels apart, turned by @a degrees, their
/// centres around the intermediate image's.
IntermediateMap turnedMap(double step, int imageSize, double degrees = 30.0) {
    const double angle = degrees * M_PI / 180.0, half = 0.5 * (imageSize - 1);
    const double c = step * std::cos(angle), s = step * std::sin(angle);
    return {20.0 - half * (c - s), c, -s, 18.0 - half * (s + c), s, c};
}

bool sameImages(const Framebuffer& a, const Framebuffer& b) {
    return a.rgba.size() == b.rgba.size() &&
           std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

/// With only the lit texel's row and column marked reached, the image must be the
/// one drawn when every row is reached: the warp may skip only where no tap reaches.
void expectNoLightLostAroundTexels(double step, double degrees) {
    const int size = step < 1.0 ? 80 : 16;  // wide enough to cover the image when turned
    const IntermediateMap map = turnedMap(step, size, degrees);
    for (int y = 1; y < 20; ++y) {
        for (int x = 1; x < 20; ++x) {
            IntermediateImage image = oneTexel(x, y);
            const Framebuffer everywhere = warpToImage(image, map, size, size);
            ASSERT_GT(test::opacitySum(everywhere), 0.0) << "the texel must be seen";
            image.reached.assign(image.height, PixelSpan{});
            image.reached[y] = {x, x};
            EXPECT_TRUE(sameImages(warpToImage(image, map, size, size), everywhere))
                << "texel (" << x << ", " << y << "), " << step << " intermediate pixels a pixel, turned " << degrees
                << " degrees";
        }
    }
}

TEST(Warp, PixelsSeeLightJustBeyondTheReachedSpans) {
    // Texels on both sides of the warp's tiles; a pixel's footprint smaller than an
    // intermediate pixel (two taps a side) and larger (four a side); the image turned,
    // or along the intermediate image's axes.
    for (const double degrees : {30.0, 0.0}) {
        for (const double step : {0.7, 3.6}) expectNoLightLostAroundTexels(step, degrees);
    }
}

TEST(Warp, RowsThatNothingReachedStayTransparent) {
    IntermediateImage image = oneTexel(12, 9);
    image.reached.assign(image.height, PixelSpan{});
    EXPECT_EQ(test::opacitySum(warpToImage(image, turnedMap(0.7, 48), 48, 48)), 0.0);
}

TEST(Warp, MapsBeyondTheImageOrNotANumberGiveTransparentPixels) {
    const IntermediateImage image = oneTexel(12, 9);
    EXPECT_EQ(test::opacitySum(warpToImage(image, {1e9, 1.0, 0.0, -1e9, 0.0, 1.0}, 8, 8)), 0.0);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(test::opacitySum(warpToImage(image, {nan, 1.0, 0.0, 0.0, 0.0, 1.0}, 8, 8)), 0.0);
}

/// A 40 x 36 intermediate image whose opacity waves along its rows, @a period texels
/// long, between 0.1 and 0.9; every row reached.
IntermediateImage wave(double period) {
    IntermediateImage image;
    image.width = 40;
    image.height = 36;
    image.rgba.resize(std::size_t(image.width) * image.height * 4);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const float alpha = float(0.5 + 0.4 * std::cos(2.0 * M_PI * x / period));
            float* texel = image.rgba.data() + (std::size_t(y) * image.width + x) * 4;
            texel[0] = texel[1] = texel[2] = 0.5f * alpha;
            texel[3] = alpha;
        }
    }
    image.reached.assign(image.height, PixelSpan{0, image.width - 1});
    return image;
}

// Detail between texels keeps its contrast: a wave six texels long, the pixels'
// centres halfway between texels, keeps 82% of its swing through Catmull-Rom taps,
// where bilinear ones kept 75% (the wave itself averaged over each pixel keeps 83%).
TEST(Warp, DetailBetweenTexelsKeepsItsContrast) {
    const IntermediateImage image = wave(6.0);
    const IntermediateMap halfwayBetween{2.5, 1.0, 0.0, 2.0, 0.0, 1.0};
    const Framebuffer pixels = warpToImage(image, halfwayBetween, 32, 30);
    float lowest = 1.0f, highest = 0.0f;
    for (int x = 0; x < 30; ++x) {
        const float alpha = pixels.pixel(x, 15)[3];
        lowest = std::min(lowest, alpha);
        highest = std::max(highest, alpha);
    }
    EXPECT_GT((highest - lowest) / 0.8f, 0.8f);
}

// Catmull-Rom's negative lobes overshoot beside a sharp edge; a pixel must still be
// premultiplied colour: 0 <= colour <= opacity <= 1.
TEST(Warp, PixelsBesideSharpEdgesStayValidPremultipliedColour) {
    IntermediateImage image = oneTexel(20, 18);
    float* texel = image.rgba.data() + (std::size_t(18) * image.width + 20) * 4;
    for (int c = 0; c < 4; ++c) texel[c] = 1.0f;  // opaque white beside transparent black
    for (const double step : {0.7, 1.0, 3.6}) {
        const Framebuffer pixels = warpToImage(image, turnedMap(step, 24), 24, 24);
        ASSERT_GT(test::opacitySum(pixels), 0.0) << step;
        for (int y = 0; y < 24; ++y) {
            for (int x = 0; x < 24; ++x) {
                const float* p = pixels.pixel(x, y);
                EXPECT_GE(p[3], 0.0f);
                EXPECT_LE(p[3], 1.0f);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_GE(p[c], 0.0f) << step;
                    EXPECT_LE(p[c], p[3]) << step;
                }
            }
        }
    }
}

}  // namespace
}  // namespace gvr
