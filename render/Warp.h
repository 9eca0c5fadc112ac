/// @file Warp.h
/// @brief Shear-warp's last step: the intermediate image, composited in the stack's
/// plane, resampled onto the camera's pixels.
#pragma once

#include "render/Framebuffer.h"

#include <cstdint>
#include <vector>

namespace gvr {

/// Pixels [first, last] of a row; empty when first > last.
struct PixelSpan {
    int first = INT32_MAX, last = INT32_MIN;
    bool empty() const { return first > last; }
};

/// The slices sheared for a direction and composited front to back, in the stack's plane.
struct IntermediateImage {
    int width = 0, height = 0;
    int originX = 0, originY = 0;  ///< stack sample coordinates of pixel (0, 0)
    std::vector<float> rgba;       ///< premultiplied
    /// Per row, the pixels that compositing reached: every pixel outside is zero.
    std::vector<PixelSpan> reached;
};

/// Where the ray of image pixel (x, y) meets the front slice, in intermediate
/// pixels: u = u0 + x dux + y duy, and v likewise (orthographic rays, so affine).
struct IntermediateMap {
    double u0, dux, duy, v0, dvx, dvy;
};

/// The image of @a width x @a height pixels, each the average of the intermediate
/// image over the pixel's footprint on it (bilinear taps spread over it, as the
/// anti-aliased ray marcher spreads its rays); transparent beyond it.
Framebuffer warpToImage(const IntermediateImage& intermediate, const IntermediateMap& map, int width, int height);

}  // namespace gvr
