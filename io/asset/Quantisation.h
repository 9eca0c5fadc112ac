/// @file Quantisation.h
/// @brief Uniform quantisation of a value range and the "smallest three" rotation
/// packing, as both asset bodies (format 1 and format 2) store them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gvr {

/// The nearest of the 2^bits evenly spaced levels from @a lo to @a hi (0 when the range is empty).
inline std::uint32_t quantise(float value, float lo, float hi, int bits) {
    const std::uint32_t levels = (1u << bits) - 1u;
    if (!(hi > lo)) return 0;
    const double t = std::clamp((double(value) - lo) / (double(hi) - lo), 0.0, 1.0);
    return std::uint32_t(std::lround(t * levels));
}

inline float dequantise(std::uint32_t q, float lo, float hi, int bits) {
    return float(lo + (double(hi) - lo) * (double(q) / double((1u << bits) - 1u)));
}

/// "Smallest three": the three stored components of a unit quaternion are in @a q;
/// this fills in the largest one, @a q[largest], which was made positive when packed
/// (q and -q are the same rotation).
inline void completeQuaternion(int largest, float q[4]) {
    float sumSquares = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (k != largest) sumSquares += q[k] * q[k];
    }
    q[largest] = std::sqrt(std::max(0.0f, 1.0f - sumSquares));
}

}  // namespace gvr
