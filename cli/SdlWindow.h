/// @file SdlWindow.h
/// @brief A desktop window (SDL2) that shows the renderer's framebuffers over
/// black, with a few lines of text on top. No GPU needed: the image is a texture
/// that SDL's software or GL renderer copies to the screen.
#pragma once

#include "render/Framebuffer.h"

#include <string>
#include <vector>

struct SDL_Window;
struct SDL_Renderer;
struct SDL_Texture;
typedef struct _TTF_Font TTF_Font;

namespace gvr {

class SdlWindow {
public:
    /// Opens a resizable window of @a width x @a height pixels.
    /// @throw InputError naming "display" when there is none (no X server, ...).
    SdlWindow(const std::string& title, int width, int height);
    ~SdlWindow();
    SdlWindow(const SdlWindow&) = delete;
    SdlWindow& operator=(const SdlWindow&) = delete;

    /// The size of the image to render now, in pixels (it follows resizes).
    std::pair<int, int> size() const;

    /// Shows @a image (premultiplied RGBA, over black) with @a lines of text at the
    /// top left; the text is left out when the font cannot be opened.
    void show(const Framebuffer& image, const std::vector<std::string>& lines);

private:
    void close();
    void drawText(const std::vector<std::string>& lines);

    SDL_Window* mWindow = nullptr;
    SDL_Renderer* mRenderer = nullptr;
    SDL_Texture* mTexture = nullptr;
    TTF_Font* mFont = nullptr;
    int mTextureWidth = 0, mTextureHeight = 0;
    std::vector<unsigned char> mPixels;
};

}  // namespace gvr
