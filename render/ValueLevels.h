/// @file ValueLevels.h
/// @brief How a stack of grey values keeps them (16-bit codes) and how they are
/// classified when composited (levels of the transfer function).
#pragma once

#include "pipeline/TransferFunction.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gvr {

/// How a slice of values keeps them: as 16-bit codes spread evenly from its least
/// value to its greatest (ValueLevels::codingFor), in half a float's bytes. A code,
/// or a code interpolated between codes, stands for a level of the transfer
/// function, which compositing reads.
struct ValueCoding {
    static constexpr int kLastCode = 65535;
    double lowest = 0.0, codesPerValue = 0.0;       ///< the value of code 0, and codes per unit of value
    float firstLevel = 0.0f, levelsPerCode = 0.0f;  ///< the (fractional) level of code 0, and levels per code

    /// The nearest code to @a value; values beyond the codes take the end ones.
    std::uint16_t code(float value) const {
        const double c = (double(value) - lowest) * codesPerValue + 0.5;
        if (!(c > 0.0)) return 0;
        return c >= kLastCode ? std::uint16_t(kLastCode) : std::uint16_t(c);
    }
    /// The value @a code stands for.
    double value(float code) const { return codesPerValue > 0.0 ? lowest + code / codesPerValue : lowest; }
    /// The level, fractional, that @a code stands for: ValueLevels::nearest rounds it.
    float level(float code) const { return firstLevel + code * levelsPerCode; }
};

/// The classification of a stack of values, in levels: the transfer function at
/// kCount values spread evenly over its points (it is constant beyond them), with
/// opacity over one slice spacing. A resampled value takes its nearest level.
class ValueLevels {
public:
    static constexpr int kCount = 4096;

    ValueLevels(const TransferFunction& tf, double sliceSpacingVoxels);
    int levelOf(float value) const { return mScale.levelOf(value); }
    /// The level nearest to fractional level @a level (ValueCoding::level).
    static int nearest(float level) {
        const float rounded = level + 0.5f;
        if (!(rounded > 0.0f)) return 0;
        return rounded >= float(kCount - 1) ? kCount - 1 : int(rounded);
    }
    /// Straight colour and the opacity of one slice spacing.
    const std::array<float, 4>& rgba(int level) const { return mRgba[level]; }
    /// The fractional level below which every nearest level is transparent: minus
    /// infinity when level 0 can be seen, and beyond the last level when none can.
    float darkBelow() const { return mDarkBelow; }
    /// The coding of values from @a lo to @a hi, and no further than kCodeReach spans
    /// of the transfer function beyond its points: a value that far off classifies
    /// as its end level all the same, and resamples with its neighbours little
    /// differently, while the codes keep a 500th of the span or finer.
    ValueCoding codingFor(float lo, float hi) const;
    /// Whether some value in [lo, hi] has a level that is not transparent.
    bool anyVisible(float lo, float hi) const { return anyVisibleLevel(levelOf(lo), levelOf(hi)); }
    /// Whether some level in [lo, hi] is not transparent (none when lo > hi).
    bool anyVisibleLevel(int lo, int hi) const { return hi >= lo && mVisibleFrom[lo] <= hi; }
    /// anyVisibleLevel(lo[n], hi[n]) into seen[n] for each n below @a count.
    void markVisible(const std::uint16_t* lo, const std::uint16_t* hi, std::size_t count, std::uint8_t* seen) const;

private:
    /// Values to levels. In double precision, so that any span of float values, from
    /// the gap between two denormals to the whole float range, has finite levels per unit.
    struct Scale {
        double first, perValue;  ///< the value of level 0, and levels per unit of value
        int levelOf(float value) const {
            const double level = (double(value) - first) * perValue + 0.5;
            if (!(level > 0.0)) return 0;  // NaN too
            return level >= double(kCount - 1) ? kCount - 1 : int(level);
        }
    };

    static constexpr double kCodeReach = 64.0;
    Scale mScale;
    float mDarkBelow;
    std::vector<std::array<float, 4>> mRgba;
    /// The first visible level at or above each level (kCount for none): a range's
    /// test in one read of a table small enough to stay in cache.
    std::vector<std::uint16_t> mVisibleFrom;
};

}  // namespace gvr
