#include "cli/SdlWindow.h"
#include "pipeline/Error.h"
#include "tests/ScopedEnvironment.h"
#include "tests/TestHelpers.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <array>
#include <string>

namespace gvr {
namespace {

/// The renderer of the only window open. SDL numbers the windows of each start of
/// its video system from 1.
SDL_Renderer* onlyRenderer() {
    for (Uint32 id = 1; id <= 16; ++id) {
        if (SDL_Window* window = SDL_GetWindowFromID(id)) return SDL_GetRenderer(window);
    }
    return nullptr;
}

std::array<unsigned char, 4> shownPixel(int x, int y) {
    std::array<unsigned char, 4> rgba{};
    const SDL_Rect one{x, y, 1, 1};
    SDL_RenderReadPixels(onlyRenderer(), &one, SDL_PIXELFORMAT_RGBA32, rgba.data(), 4);
    return rgba;
}

/// What opening a window throws; "" when one opens.
std::string openingError() {
    return test::errorMessageOf<InputError>([] { SdlWindow window("gvr test", 64, 48); });
}

TEST(SdlWindow, WithoutADisplayItIsAnErrorNamingTheDisplay) {
    const test::ScopedEnvironment noX("DISPLAY", std::nullopt), noWayland("WAYLAND_DISPLAY", std::nullopt),
        noDriver("SDL_VIDEODRIVER", std::nullopt);
    const std::string error = openingError();
    EXPECT_EQ(error.rfind("display: ", 0), 0u) << "'" << error << "'";
}

TEST(SdlWindow, AnUnknownDriverIsAnErrorNamingTheDisplay) {
    const test::ScopedEnvironment driver("SDL_VIDEODRIVER", "no-such-driver");
    const std::string error = openingError();
    EXPECT_EQ(error.rfind("display: ", 0), 0u) << "'" << error << "'";
}

TEST(SdlWindow, ShowsThePremultipliedImageOverBlackClampedToBytes) {
    // The driver a user asks for by name is allowed, and needs no display.
    const test::ScopedEnvironment driver("SDL_VIDEODRIVER", "dummy");
    SdlWindow window("gvr test", 64, 48);
    EXPECT_EQ(window.size(), std::make_pair(64, 48));
    for (const auto& [width, height] : {std::make_pair(4, 3), std::make_pair(7, 5)}) {  // a resize remakes the texture
        Framebuffer image(width, height);
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                float* p = image.pixel(x, y);
                p[0] = 0.5f, p[1] = 1.5f, p[2] = -0.25f, p[3] = 0.5f;
            }
        }
        window.show(image, {"a line of text, top left"});
        // Bottom right, clear of the text: the image stretched over the window.
        EXPECT_EQ(shownPixel(60, 44), (std::array<unsigned char, 4>{128, 255, 0, 255})) << width << "x" << height;
    }
}

}  // namespace
}  // namespace gvr
