#include "cli/SdlWindow.h"

#include "pipeline/Error.h"

#include <SDL.h>
#include <SDL_ttf.h>

#include <algorithm>

namespace gvr {

namespace {

/// Debian's fonts-dejavu-core: a monospaced font keeps the HUD's columns still.
constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf";
constexpr int kFontPoints = 14;

unsigned char toByte(float value) { return static_cast<unsigned char>(std::clamp(value, 0.0f, 1.0f) * 255.0f + 0.5f); }

}  // namespace

SdlWindow::SdlWindow(const std::string& title, int width, int height) {
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        throw InputError("display", std::string("no window can open: ") + SDL_GetError());
    // Without a display SDL falls back to drawing off screen: a window nobody sees
    // and nobody can close. Only a user who asks for that driver gets it.
    const std::string driver = SDL_GetCurrentVideoDriver();
    if ((driver == "offscreen" || driver == "dummy") && !SDL_getenv("SDL_VIDEODRIVER")) {
        SDL_Quit();
        throw InputError("display",
                         "none found (DISPLAY and WAYLAND_DISPLAY unset or unreachable); run gvr view on a "
                         "desktop, over ssh -X, or under xvfb-run");
    }
    mWindow = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, width, height,
                               SDL_WINDOW_RESIZABLE);
    if (mWindow) mRenderer = SDL_CreateRenderer(mWindow, -1, 0);
    if (!mRenderer) {
        const std::string problem = SDL_GetError();
        close();
        throw InputError("display", "no window can open: " + problem);
    }
    if (TTF_Init() == 0) mFont = TTF_OpenFont(kFontPath, kFontPoints);
}

SdlWindow::~SdlWindow() { close(); }

void SdlWindow::close() {
    if (mFont) TTF_CloseFont(mFont);
    mFont = nullptr;
    if (TTF_WasInit()) TTF_Quit();
    if (mTexture) SDL_DestroyTexture(mTexture);
    if (mRenderer) SDL_DestroyRenderer(mRenderer);
    if (mWindow) SDL_DestroyWindow(mWindow);
    mTexture = nullptr;
    mRenderer = nullptr;
    mWindow = nullptr;
    SDL_Quit();
}

std::pair<int, int> SdlWindow::size() const {
    int width = 0, height = 0;
    SDL_GetRendererOutputSize(mRenderer, &width, &height);
    return {std::max(width, 1), std::max(height, 1)};
}

void SdlWindow::show(const Framebuffer& image, const std::vector<std::string>& lines) {
    if (!mTexture || mTextureWidth != image.width || mTextureHeight != image.height) {
        if (mTexture) SDL_DestroyTexture(mTexture);
        mTexture = SDL_CreateTexture(mRenderer, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, image.width,
                                     image.height);
        mTextureWidth = image.width;
        mTextureHeight = image.height;
    }
    // Premultiplied colour over black is the colour itself.
    mPixels.resize(image.rgba.size());
    for (std::size_t p = 0; p < image.rgba.size(); p += 4) {
        for (int c = 0; c < 3; ++c) mPixels[p + c] = toByte(image.rgba[p + c]);
        mPixels[p + 3] = 255;
    }
    SDL_UpdateTexture(mTexture, nullptr, mPixels.data(), image.width * 4);
    SDL_RenderClear(mRenderer);
    SDL_RenderCopy(mRenderer, mTexture, nullptr, nullptr);
    drawText(lines);
    SDL_RenderPresent(mRenderer);
}

void SdlWindow::drawText(const std::vector<std::string>& lines) {
    if (!mFont) return;
    const SDL_Color colour{255, 255, 160, 255};
    int y = 4;
    for (const std::string& line : lines) {
        if (line.empty()) continue;
        SDL_Surface* surface = TTF_RenderUTF8_Blended(mFont, line.c_str(), colour);
        if (!surface) continue;
        SDL_Texture* text = SDL_CreateTextureFromSurface(mRenderer, surface);
        const SDL_Rect where{6, y, surface->w, surface->h};
        y += surface->h;
        SDL_FreeSurface(surface);
        if (!text) continue;
        SDL_RenderCopy(mRenderer, text, nullptr, &where);
        SDL_DestroyTexture(text);
    }
}

}  // namespace gvr
