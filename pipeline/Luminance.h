/// @file Luminance.h
/// @brief The one grey value gvr takes from a colour: thresholds, ranges and
/// derived densities of RGB data all use it.
#pragma once

namespace gvr {

/// Rec. 709 luma of anything indexable as r, g, b (a float*, Vec3s, std::array).
template <typename RGB>
double luminance(const RGB& rgb) {
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/// The value thresholds and ranges compare, of a sample of @a channels floats: the
/// value itself for grey data, the luminance for RGB.
inline double sampleKey(const float* value, int channels) {
    return channels >= 3 ? luminance(value) : double(value[0]);
}

}  // namespace gvr
