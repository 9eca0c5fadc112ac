/// @file ValueRange.h
/// @brief The least and greatest of many floats, four at a time: stack builds take
/// the range of every plane and of every leaf, where std::minmax_element's
/// branches cost more than the rest of the work on the values.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

namespace gvr {

/// The least and greatest of @a size values, NaN left out (infinities for none).
inline std::pair<float, float> valueRange(const float* values, std::size_t size) {
    float lo = INFINITY, hi = -INFINITY;
    std::size_t n = 0;
#if defined(__SSE2__)
    __m128 least = _mm_set1_ps(INFINITY), greatest = _mm_set1_ps(-INFINITY);
    // The four-wide loop's end named first: GCC otherwise warns that the loop after it
    // may run for ever (-Waggressive-loop-optimizations), a leaf's 512 values inlined.
    const std::size_t fours = size - size % 4;
    for (; n < fours; n += 4) {
        const __m128 v = _mm_loadu_ps(values + n);
        least = _mm_min_ps(v, least);  // the second operand where v is NaN
        greatest = _mm_max_ps(v, greatest);
    }
    float lanes[8];
    _mm_storeu_ps(lanes, least);
    _mm_storeu_ps(lanes + 4, greatest);
    lo = std::min({lo, lanes[0], lanes[1], lanes[2], lanes[3]});
    hi = std::max({hi, lanes[4], lanes[5], lanes[6], lanes[7]});
#endif
    for (; n < size; ++n) {
        lo = std::min(lo, values[n]);
        hi = std::max(hi, values[n]);
    }
    return {lo, hi};
}

}  // namespace gvr
