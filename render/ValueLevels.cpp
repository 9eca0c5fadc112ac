#include "render/ValueLevels.h"

#include "render/ValueRange.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace gvr {

namespace {

/// ValueLevels::markVisible's loop, without branches: a stack build judges every
/// cell of every slice (one at a time, with a test for each neighbouring slice,
/// chest CT builds took longer: docs/benchmarks.md, "Render speed").
__attribute__((target_clones("avx2", "default"))) void markVisibleLevels(const std::uint16_t* lo,
                                                                         const std::uint16_t* hi, std::size_t count,
                                                                         const std::uint16_t* visibleFrom,
                                                                         std::uint8_t* seen) {
    for (std::size_t n = 0; n < count; ++n) {
        seen[n] = std::uint8_t(hi[n] >= lo[n]) & std::uint8_t(visibleFrom[lo[n]] <= hi[n]);
    }
}

}  // namespace

void ValueLevels::markVisible(const std::uint16_t* lo, const std::uint16_t* hi, std::size_t count,
                              std::uint8_t* seen) const {
    markVisibleLevels(lo, hi, count, mVisibleFrom.data(), seen);
}

ValueLevels::ValueLevels(const TransferFunction& tf, double sliceSpacingVoxels) : mRgba(kCount), mVisibleFrom(kCount) {
    // Stored values are floats: points beyond the float range change nothing they can
    // reach, and clamping keeps the span, and so the levels per unit, finite.
    const double first = std::clamp(tf.points().front().value, -double(FLT_MAX), double(FLT_MAX));
    const double last = std::clamp(tf.points().back().value, -double(FLT_MAX), double(FLT_MAX));
    mScale = {first, last > first ? (kCount - 1) / (last - first) : 0.0};
    for (int level = 0; level < kCount; ++level) {
        const double value = mScale.perValue > 0.0 ? first + level / mScale.perValue : first;
        mRgba[level] = tf(value);
        mRgba[level][3] = opacityOverLength(mRgba[level][3], sliceSpacingVoxels);
    }
    for (int level = kCount - 1, next = kCount; level >= 0; --level) {
        if (mRgba[level][3] > 0.0f) next = level;
        mVisibleFrom[level] = std::uint16_t(next);
    }
    const int level = mVisibleFrom[0];
    if (level == kCount) {
        mDarkBelow = INFINITY;
    } else if (level == 0) {
        mDarkBelow = -INFINITY;
    } else {
        mDarkBelow = float(level) - 0.5f;  // nearest rounds halves up
    }
}

ValueCoding ValueLevels::codingFor(float lo, float hi) const {
    double from = lo, to = hi;
    if (mScale.perValue > 0.0) {
        const double span = (kCount - 1) / mScale.perValue;
        from = std::max(from, mScale.first - kCodeReach * span);
        to = std::min(to, mScale.first + (kCodeReach + 1.0) * span);
    }
    ValueCoding coding;
    coding.lowest = from;
    // Equal ends, or a span beyond the doubles: every value takes code 0.
    const double codesPerValue = ValueCoding::kLastCode / (to - from);
    if (to > from && std::isfinite(codesPerValue)) coding.codesPerValue = codesPerValue;
    coding.firstLevel = float((from - mScale.first) * mScale.perValue);
    coding.levelsPerCode = coding.codesPerValue > 0.0 ? float(mScale.perValue / coding.codesPerValue) : 0.0f;
    return coding;
}

}  // namespace gvr
