// The warp: an image pixel sees the intermediate image's light wherever its taps
// reach it, whichever rows compositing reached.
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

}  // namespace
}  // namespace gvr
