/// @file Framebuffer.h
/// @brief What the renderers return: premultiplied RGBA floats, rows top to bottom.
#pragma once

#include "pipeline/FloatVolume.h"

#include <vector>

namespace gvr {

struct Framebuffer {
    int width = 0, height = 0;
    std::vector<float> rgba;  ///< 4 floats per pixel, colour premultiplied by alpha, in [0, 1]

    Framebuffer() = default;
    Framebuffer(int w, int h) : width(w), height(h), rgba(std::size_t(w) * h * 4, 0.0f) {}
    float* pixel(int x, int y) { return rgba.data() + (std::size_t(y) * width + x) * 4; }
    const float* pixel(int x, int y) const { return rgba.data() + (std::size_t(y) * width + x) * 4; }
};

/// The image as a one-sample-deep volume of 4 channels, for the quality metrics.
inline FloatVolume asVolume(const Framebuffer& image) {
    FloatVolume volume(openvdb::Coord(image.width, image.height, 1), 4);
    volume.values = image.rgba;
    return volume;
}

}  // namespace gvr
