/// @file CompositeRows.h
/// @brief The shear-warp compositor's intermediate rows: their pixels (side by side or
/// in planes), which of them still take light, and where each ray last resampled.
/// Internal to the renderer (ShearWarp.cpp).
#pragma once

#include "pipeline/FastExp.h"
#include "render/ShearWarp.h"

#include <cstdint>
#include <numeric>
#include <vector>

namespace gvr::compositing {

/// Where each pixel of an intermediate row last resampled a stack of values: the
/// (fractional) level and the slice, so that the stretch of its ray from there to
/// the next slice can be pre-integrated.
struct RayEnd {
    float level = 0.0f;
    /// The slice, counted front to back from 2, so that the 0 of a fresh row never
    /// passes for the slice before the first.
    std::uint32_t stamp = 0;
};

/// One row's RayEnds, and the stamp of the slice being composited.
struct RayEnds {
    RayEnd* last;
    std::uint32_t stamp;
};

/// The pixels of one intermediate row that still take light. Each pixel links to
/// the first open pixel at or after it, so a stretch of opaque pixels is stepped
/// over in one jump (Lacroute and Levoy's opaque-pixel links).
class OpenPixels {
public:
    void reset(int width) {
        mNext.resize(width + 1);  // the last entry is the end: always open
        std::iota(mNext.begin(), mNext.end(), 0);
    }
    /// The first open pixel at or after @a p (the width when none is).
    int next(int p) {
        while (mNext[p] != p) {
            mNext[p] = mNext[mNext[p]];  // halve the path for the next search
            p = mNext[p];
        }
        return p;
    }
    void close(int p) { mNext[p] = p + 1; }

private:
    std::vector<int> mNext;
};

/// A vector at a float's alignment, read and written typed, unlike memcpy's, so
/// that the compiler knows that a store changes only floats. Packed, since clang
/// keeps a vector typedef's own alignment whatever its aligned attribute says.
template <typename Vector>
struct __attribute__((packed)) Unaligned {
    Vector values;
};

/// An intermediate row's pixels, RGBA side by side: a pixel is one register.
struct InterleavedRow {
    float* rgba;
    /// Adds @a light behind pixel @a p, closing it once it is opaque enough.
    void add(int p, Floats4 light, float termination, OpenPixels& open) const {
        Unaligned<Floats4>& pixel = *reinterpret_cast<Unaligned<Floats4>*>(rgba + std::size_t(p) * 4);
        Floats4 value = pixel.values;
        value += (1.0f - value[3]) * light;
        pixel.values = value;
        if (value[3] >= termination) open.close(p);
    }
};

/// An intermediate row's pixels, a plane per channel: eight neighbouring pixels'
/// channel is one register, and their light four, where side by side it took a
/// register per two pixels and the instructions to move light and opacity there.
struct PlanarRow {
    float* planes;  ///< red, green, blue and opacity, each `width` floats
    int width;
    float* channel(int c) const { return planes + std::size_t(c) * width; }
    /// As InterleavedRow's: the same operations on the same floats.
    void add(int p, Floats4 light, float termination, OpenPixels& open) const {
        const float clear = 1.0f - channel(3)[p];
        for (int c = 0; c < 4; ++c) channel(c)[p] += clear * light[c];
        if (channel(3)[p] >= termination) open.close(p);
    }
};

}  // namespace gvr::compositing
