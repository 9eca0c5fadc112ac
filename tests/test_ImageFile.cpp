// Rendered frames out: PNG as straight 8-bit RGBA, EXR as the premultiplied floats
// themselves, and nothing written for a format gvr does not write.

#include "io/formats/ImageFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace gvr {
namespace {

/// The pixels of @a path as @a type, alpha as stored (never premultiplied on reading).
template <typename T>
std::vector<T> readPixels(const std::string& path, OIIO::TypeDesc type, int& width, int& height) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) return {};
    width = in->spec().width;
    height = in->spec().height;
    std::vector<T> pixels(std::size_t(width) * height * 4);
    EXPECT_EQ(in->spec().nchannels, 4) << path;
    EXPECT_TRUE(in->read_image(0, 0, 0, 4, type, pixels.data())) << in->geterror();
    return pixels;
}

TEST(ImageFile, PngHoldsStraightAlphaRoundedAndClamped) {
    test::TempDir dir;
    const std::vector<float> premultiplied{
        0.25f, 0.5f,  0.0f,  0.5f,  // half transparent: colours are divided by alpha
        0.3f,  0.3f,  0.3f,  0.0f,  // fully transparent: black, whatever the colour
        2.0f,  -1.0f, 0.2f,  1.0f,  // out of range: clamped
        0.75f, 0.75f, 0.75f, 1.5f   // alpha above 1: colour 0.5, alpha clamped
    };
    writeImage(dir.path("f.png"), 2, 2, premultiplied.data());
    int width = 0, height = 0;
    const std::vector<std::uint8_t> bytes =
        readPixels<std::uint8_t>(dir.path("f.png"), OIIO::TypeDesc::UINT8, width, height);
    EXPECT_EQ(width, 2);
    EXPECT_EQ(height, 2);
    const std::vector<std::uint8_t> expected{128, 255, 0, 128, 0, 0, 0, 0, 255, 0, 51, 255, 128, 128, 128, 255};
    EXPECT_EQ(bytes, expected);
}

TEST(ImageFile, ExrKeepsThePremultipliedFloatsExactlyInRowOrder) {
    test::TempDir dir;
    // 3 x 2, so that a transposed or flipped image would not match.
    std::vector<float> pixels(3 * 2 * 4);
    for (std::size_t n = 0; n < pixels.size(); ++n) pixels[n] = float(n) * 0.1f - 0.5f;
    pixels[3] = 0.0f;           // emission with no coverage stays as it is
    pixels[5] = 1e30f;          // beyond 8 bits and beyond half floats
    pixels[6] = std::nanf("");  // a NaN is written, not hidden
    writeImage(dir.path("f.exr"), 3, 2, pixels.data());
    int width = 0, height = 0;
    const std::vector<float> back = readPixels<float>(dir.path("f.exr"), OIIO::TypeDesc::FLOAT, width, height);
    EXPECT_EQ(width, 3);
    EXPECT_EQ(height, 2);
    ASSERT_EQ(back.size(), pixels.size());
    for (std::size_t n = 0; n < pixels.size(); ++n) {
        if (n == 6) {
            EXPECT_TRUE(std::isnan(back[n]));
        } else {
            EXPECT_EQ(back[n], pixels[n]) << n;
        }
    }
}

TEST(ImageFile, TheExtensionIsReadWithoutRegardToCase) {
    test::TempDir dir;
    const std::vector<float> pixels(4, 1.0f);
    writeImage(dir.path("f.PNG"), 1, 1, pixels.data());
    int width = 0, height = 0;
    EXPECT_EQ(readPixels<std::uint8_t>(dir.path("f.PNG"), OIIO::TypeDesc::UINT8, width, height),
              std::vector<std::uint8_t>(4, 255));
}

TEST(ImageFile, AnotherFormatIsRefusedNamingTheFileAndWritesNothing) {
    test::TempDir dir;
    const std::vector<float> pixels(4, 0.5f);
    for (const char* name : {"f.jpg", "f.tif", "frame"}) {
        const std::string path = dir.path(name);
        const std::string message = test::errorMessageOf<InputError>([&] { writeImage(path, 1, 1, pixels.data()); });
        EXPECT_EQ(message.rfind(path + ": unknown image format '", 0), 0u) << message;
        EXPECT_NE(message.find("write .png (8-bit) or .exr (float)"), std::string::npos) << message;
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.root()));
}

}  // namespace
}  // namespace gvr
