/// @file LightTables.h
/// @brief What a resampled sample adds over the oblique path through a slice, read from
/// tables built once a frame from the transfer function: classified samples,
/// values, pre-integrated segments and colours. Internal to the renderer.
#pragma once

#include "render/CompositeRows.h"
#include "render/SliceStack.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gvr::compositing {

/// Opacity and colour factor for a path 1/cos(angle) slices long, per 16-bit
/// opacity level: the view may cross the slices obliquely when the stack is reused.
class ObliquityTable {
public:
    explicit ObliquityTable(double lengthRatio) : mLevels(65536) {
        // ln(1 - alpha) per level never changes, so each frame needs one exp a level:
        // 1 - (1 - alpha)^r = 1 - exp(r ln(1 - alpha)).
        static const std::vector<double> logTransmittance = [] {
            std::vector<double> table(65536);
            for (int level = 0; level < 65536; ++level) table[level] = std::log1p(-level / 65535.0);
            return table;
        }();
        for (int level = 0; level < 65536; ++level) {
            const float opacity = float(1.0 - std::exp(lengthRatio * logTransmittance[level]));
            // Colours are stored x 65535 like opacity, so the factor also scales them to [0, 1].
            mLevels[level] = {opacity, level > 0 ? opacity / level : 1.0f / 65535.0f};
        }
    }
    /// The premultiplied RGBA that a weighted sum of stored samples (x 65535)
    /// adds over the oblique path.
    Floats4 operator()(Floats4 stored) const {
        const Level& level = mLevels[std::min(65535, int(stored[3] + 0.5f))];
        Floats4 out = stored * level.colourFactor;
        out[3] = level.opacity;
        return out;
    }

private:
    struct Level {
        float opacity, colourFactor;  // side by side: one cache line per lookup
    };
    std::vector<Level> mLevels;
};

/// What a classified sample, or a sum of them, adds over the oblique path.
struct ClassifiedLightTable {
    using Row = InterleavedRow;
    const ObliquityTable& oblique;
    static bool dark(int, Floats4 stored) { return stored[3] <= 0.0f; }
    Floats4 operator()(Floats4 stored) const { return oblique(stored); }
    ClassifiedLightTable lookup(RayEnds, const ValueCoding&) const { return *this; }
};

/// What a value resampled from a stack of values adds over the oblique path: the
/// transfer function's premultiplied colour and opacity at its level, per frame.
/// The stack holds codes; each slice's coding turns a resampled code into a level.
class ValueLightTable {
public:
    using Sample = std::uint16_t;
    using Row = PlanarRow;
    ValueLightTable(const ValueLevels& levels, double lengthRatio)
        : mLight(ValueLevels::kCount + 1), mDarkBelow(levels.darkBelow()) {
        for (int level = 0; level < ValueLevels::kCount; ++level) {
            const std::array<float, 4>& rgba = levels.rgba(level);
            const float opacity = opacityOverLength(rgba[3], lengthRatio);
            mLight[level] = Floats4{rgba[0] * opacity, rgba[1] * opacity, rgba[2] * opacity, opacity};
        }
    }

    /// The table's reader, held by value where pixels are composited: the compiler
    /// must reload what a pixel's store might change, and a copy's floats it need not.
    /// It reads taps weighed in levels (codes times ValueCoding::levelsPerCode): a
    /// resampled level is the taps' sum plus the slice's first level. Entry kCount,
    /// after the levels, adds nothing: where dark pixels go when lanes cannot skip them.
    struct Lookup {
        const Floats4* light;
        float firstLevel, darkBelow;
        /// Levels below every visible one add nothing: a comparison spares the table.
        bool dark(int, float taps) const { return taps + firstLevel < darkBelow; }
        Floats4 operator()(float taps) const { return light[ValueLevels::nearest(taps + firstLevel)]; }
    };
    Lookup lookup(RayEnds, const ValueCoding& coding) const { return {mLight.data(), coding.firstLevel, mDarkBelow}; }
    const Floats4* table() const { return mLight.data(); }
    /// What one step of a stored code weighs, in levels.
    static float unitOf(const ValueCoding& coding) { return coding.levelsPerCode; }

private:
    std::vector<Floats4> mLight;
    float mDarkBelow;  ///< a level
};

/// Four doubles: sums over many levels, whose differences must keep the few.
using Doubles4 = double __attribute__((vector_size(32)));

/// What the stretch of a ray from one slice to the next adds, pre-integrated:
/// opacity from the extinction averaged over the values between the stretch's two
/// ends, colour weighted by extinction (Engel, Kraus and Ertl's approximation,
/// which leaves out the attenuation within one stretch). The integrals of
/// extinction and colour over the values make any stretch two reads. A stretch
/// within one level is that level's ValueLightTable.
class SegmentLightTable {
public:
    using Sample = std::uint16_t;
    using Row = InterleavedRow;
    SegmentLightTable(const ValueLevels& levels, double lengthRatio)
        : mPoints(levels, lengthRatio), mBelow(ValueLevels::kCount + 1), mDarkBelow(levels.darkBelow()) {
        mBelow[0] = Doubles4{};
        for (int level = 0; level < ValueLevels::kCount; ++level) {
            const std::array<float, 4>& rgba = levels.rgba(level);
            // An opaque level's extinction is infinite: large enough here that a
            // stretch crossing it is opaque, finite so that sums stay numbers.
            const double extinction = rgba[3] >= 1.0f ? kOpaqueExtinction : -lengthRatio * std::log1p(-double(rgba[3]));
            mBelow[level + 1] =
                mBelow[level] + Doubles4{rgba[0] * extinction, rgba[1] * extinction, rgba[2] * extinction, extinction};
        }
    }

    struct Lookup {
        const Floats4* points;
        const Doubles4* below;
        float firstLevel, darkBelow;
        RayEnds ends;
        float from = 0.0f, to = 0.0f;  ///< the levels at the ends of the stretch that dark() last looked at

        /// Notes the level that @a taps resample (as ValueLightTable's) as pixel @a p's, and
        /// whether the stretch that ends there adds nothing. A pixel that skipped the
        /// slice before (its cells, and so the stretch, could not be seen) starts
        /// afresh, as a point.
        bool dark(int p, float taps) {
            const float level = taps + firstLevel;
            RayEnd& end = ends.last[p];
            from = end.stamp == ends.stamp - 1 ? end.level : level;
            to = level;
            end = {level, ends.stamp};
            return std::max(from, to) < darkBelow;
        }

        Floats4 operator()(float) const {
            const int a = ValueLevels::nearest(from), b = ValueLevels::nearest(to);
            if (a == b) return points[b];
            const double xa = from, xb = to;
            // Out parameters: a 32-byte vector returned by value changes the ABI without AVX.
            Doubles4 atB, atA;
            integralTo(xb, b, atB);
            integralTo(xa, a, atA);
            const Doubles4 integral = atB - atA;
            const float mean = float(integral[3] / (xb - xa));
            const float opacity = 1.0f - expNonPositive(Floats4{} - mean)[0];
            // The difference keeps a few levels' worth out of thousands: floats from
            // here, which are faster. Codes reach no further than ValueLevels::codingFor's
            // spans beyond the levels, so the integrals stay far within a float's range.
            Floats4 light = __builtin_convertvector(integral, Floats4);
            // Negative for a stretch down the levels; zero for an extinction below a float's least.
            if (!(light[3] != 0.0f)) return Floats4{};
            light *= opacity / light[3];
            light[3] = opacity;
            return light;
        }

    private:
        /// The integrals from level 0's lower edge to @a x, which lies in @a level:
        /// a level holds the values within half a level of it (levelOf rounds), and
        /// beyond the end levels the transfer function is theirs.
        void integralTo(double x, int level, Doubles4& integral) const {
            const Doubles4 lo = below[level], hi = below[level + 1];
            integral = lo + (x - level + 0.5) * (hi - lo);
        }
    };
    Lookup lookup(RayEnds ends, const ValueCoding& coding) const {
        return {mPoints.table(), mBelow.data(), coding.firstLevel, mDarkBelow, ends};
    }
    static float unitOf(const ValueCoding& coding) { return ValueLightTable::unitOf(coding); }

private:
    static constexpr double kOpaqueExtinction = 1e4;
    ValueLightTable mPoints;
    std::vector<Doubles4> mBelow;  ///< integrals of colour x extinction, and of extinction, below each level
    float mDarkBelow;              ///< a level
};

/// What a colour resampled from a stack of colours adds over the oblique path: the
/// colour, with the opacity that the transfer function gives its luminance's
/// level. So colours blend before they are classified, as the ray marcher blends
/// them: a stack of classified colours fell short of the one-ray ray marcher on a
/// colour section (docs/benchmarks.md, "Stacks of colours").
class ColourLightTable {
public:
    using Sample = StackSample;
    using Row = InterleavedRow;
    ColourLightTable(const ValueLevels& levels, double lengthRatio) : mLuminance(levels, lengthRatio) {}

    struct Lookup {
        ValueLightTable::Lookup luminance;
        float opacity = 0.0f;  ///< at the taps that dark() last looked at

        /// Taps' colours are x 65535, and their luminance in levels (unitOf).
        bool dark(int, Floats4 taps) {
            opacity = luminance(taps[3])[3];
            return opacity <= 0.0f;
        }
        Floats4 operator()(Floats4 taps) const {
            Floats4 light = taps * (opacity * (1.0f / 65535.0f));
            light[3] = opacity;
            return light;
        }
    };
    Lookup lookup(RayEnds ends, const ValueCoding& coding) const { return {mLuminance.lookup(ends, coding)}; }
    /// What one stored step weighs: a 65535th of a colour, a code's levels of luminance.
    static Floats4 unitOf(const ValueCoding& coding) { return Floats4{1.0f, 1.0f, 1.0f, coding.levelsPerCode}; }

private:
    ValueLightTable mLuminance;
};

}  // namespace gvr::compositing
