// Framebuffer addressing (rows top to bottom, four floats a pixel) and its view as
// a volume for the quality metrics.

#include "render/Framebuffer.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(Framebuffer, StartsTransparentAndAddressesRowsTopToBottom) {
    Framebuffer image(3, 2);
    ASSERT_EQ(image.rgba.size(), 3u * 2u * 4u);
    for (float v : image.rgba) EXPECT_EQ(v, 0.0f);
    image.pixel(1, 1)[2] = 0.5f;  // blue of the second row's middle pixel
    EXPECT_EQ(image.rgba[(1 * 3 + 1) * 4 + 2], 0.5f);
    const Framebuffer& constant = image;
    EXPECT_EQ(constant.pixel(1, 1), image.rgba.data() + (1 * 3 + 1) * 4);
}

TEST(Framebuffer, AsVolumeIsOneSliceOfFourChannelsWithThePixelsInPlace) {
    Framebuffer image(4, 3);
    for (std::size_t n = 0; n < image.rgba.size(); ++n) image.rgba[n] = float(n) / float(image.rgba.size());
    const FloatVolume volume = asVolume(image);
    EXPECT_EQ(volume.dims, openvdb::Coord(4, 3, 1));
    EXPECT_EQ(volume.channels, 4);
    // FloatVolume runs i fastest, as the framebuffer runs x fastest: pixel (x, y) is voxel (x, y, 0).
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 4; ++x) {
            for (int c = 0; c < 4; ++c) EXPECT_EQ(volume.at(x, y, 0)[c], image.pixel(x, y)[c]);
        }
    }
}

}  // namespace
}  // namespace gvr
