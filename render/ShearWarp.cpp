#include "render/ShearWarp.h"

#include "pipeline/FastExp.h"
#include "render/Warp.h"

#include <tbb/parallel_for.h>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iterator>
#include <numeric>
#include <type_traits>

namespace gvr {

using openvdb::Vec3d;

namespace {

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

/// What a classified sample, or a sum of them, adds over the oblique path.
struct ClassifiedLight {
    using Row = InterleavedRow;
    const ObliquityTable& oblique;
    static bool dark(int, Floats4 stored) { return stored[3] <= 0.0f; }
    Floats4 operator()(Floats4 stored) const { return oblique(stored); }
    ClassifiedLight lookup(RayEnds, const ValueCoding&) const { return *this; }
};

/// What a value resampled from a stack of values adds over the oblique path: the
/// transfer function's premultiplied colour and opacity at its level, per frame.
/// The stack holds codes; each slice's coding turns a resampled code into a level.
class ValueLight {
public:
    using Sample = std::uint16_t;
    using Row = PlanarRow;
    ValueLight(const ValueLevels& levels, double lengthRatio)
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
/// within one level is that level's ValueLight.
class SegmentLight {
public:
    using Sample = std::uint16_t;
    using Row = InterleavedRow;
    SegmentLight(const ValueLevels& levels, double lengthRatio)
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

        /// Notes the level that @a taps resample (as ValueLight's) as pixel @a p's, and
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
    static float unitOf(const ValueCoding& coding) { return ValueLight::unitOf(coding); }

private:
    static constexpr double kOpaqueExtinction = 1e4;
    ValueLight mPoints;
    std::vector<Doubles4> mBelow;  ///< integrals of colour x extinction, and of extinction, below each level
    float mDarkBelow;              ///< a level
};

/// What a colour resampled from a stack of colours adds over the oblique path: the
/// colour, with the opacity that the transfer function gives its luminance's
/// level. So colours blend before they are classified, as the ray marcher blends
/// them: a stack of classified colours fell short of the one-ray ray marcher on a
/// colour section (docs/benchmarks.md, "Stacks of colours").
class ColourLight {
public:
    using Sample = StackSample;
    using Row = InterleavedRow;
    ColourLight(const ValueLevels& levels, double lengthRatio) : mLuminance(levels, lengthRatio) {}

    struct Lookup {
        ValueLight::Lookup luminance;
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
    ValueLight mLuminance;
};

float load(std::uint16_t code) { return code; }

/// Two neighbouring codes as floats, in the two lowest lanes: one load and one
/// conversion, where two scalar ones made reused frames slower than floats
/// (docs/benchmarks.md, "Render speed").
Floats4 loadPair(const std::uint16_t* codes) {
#if defined(__SSE2__)
    std::int32_t bits;
    std::memcpy(&bits, codes, sizeof bits);
    return (Floats4)_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_cvtsi32_si128(bits), _mm_setzero_si128()));
#else
    return Floats4{float(codes[0]), float(codes[1]), 0.0f, 0.0f};
#endif
}

Floats4 load(const StackSample& sample) {
#if defined(__SSE2__)
    // GCC turns a generic 16-bit to float conversion into four scalar ones.
    const __m128i bits = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(&sample));
    return (Floats4)_mm_cvtepi32_ps(_mm_unpacklo_epi16(bits, _mm_setzero_si128()));
#else
    return Floats4{float(sample.r), float(sample.g), float(sample.b), float(sample.a)};
#endif
}

/// What a pixel takes from one slice row, sheared: right x the sample in its
/// column plus left x the next. The shear is the same across one slice, and so
/// are the weights.
template <typename Sample>
struct Tap {
    using Loaded = decltype(load(Sample{}));  ///< Floats4 for classified samples, float for codes (in levels)
    const Sample* columns;                    ///< the row's samples, indexed by column
    Loaded right, left;
    Loaded operator()(int column) const {
        if constexpr (std::is_same_v<Sample, std::uint16_t>) {
            const Floats4 pair = loadPair(columns + column);
            return right * pair[0] + left * pair[1];
        } else {
            return right * load(columns[column]) + left * load(columns[column + 1]);
        }
    }
};

/// Where slice k lands on the intermediate image: intermediate row y reads slice
/// rows y + rowOffset (upper) and the one after (lower), and pixel p of it reads
/// columns p + shift (right) and the one after (left), with these weights. The same
/// for every sample of the slice, so set up once a frame.
struct SliceShear {
    int rowOffset, shift;
    float upperLeft, upperRight, lowerLeft, lowerRight;
    double row;  ///< the row of the slice, fractional, that intermediate row 0 meets
    /// The pixels whose samples lie within the volume's faces along the rows: those
    /// beyond cross nothing, though the lattice reaches a sample further.
    int firstPixel, lastPixel;
};

SliceShear shearOf(const StackGeometry& g, int k, double shiftX, double shiftY, int originX, int originY) {
    const double sy = originY + k * shiftY, sx = k * shiftX;
    const int jy = int(std::floor(sy)), ix = int(std::floor(sx));
    const float fy = float(sy - jy), fx = float(sx - ix);
    // Pixel p samples the slice at column p + originX + sx.
    const double column = originX + sx;
    const int firstPixel = int(std::ceil(g.firstColumnInside - column - 1e-6));
    const int lastPixel = int(std::floor(g.lastColumnInside - column + 1e-6));
    return {jy, originX + ix, fx * (1 - fy), (1 - fx) * (1 - fy), fx * fy, (1 - fx) * fy, sy, firstPixel, lastPixel};
}

/// One slice row's runs, seen from an intermediate row: run r reaches pixels
/// [r.begin - shift - 1, r.end - shift - 1], and its tap reads only the run and
/// its padding there.
template <typename Sample>
struct ShearedRuns {
    using Loaded = typename Tap<Sample>::Loaded;
    const RowRun* runs = nullptr;
    const RowRun* end = nullptr;
    const Sample* samples = nullptr;
    int shift = 0;
    Loaded right{}, left{};

    /// @a unit: what one stored step weighs (a Light's unitOf), 1 for classified samples.
    ShearedRuns(const Slice& slice, int row, int height, int shiftBy, float leftWeight, float rightWeight,
                Loaded unit = Loaded{} + 1.0f)
        // Loaded{} + w is w, or w in each of four lanes.
        : samples(slice.stored<Sample>().data()),
          shift(shiftBy),
          right(Loaded{} + rightWeight * unit),
          left(Loaded{} + leftWeight * unit) {
        if (row < 0 || row >= height || leftWeight + rightWeight == 0.0f) return;
        runs = slice.runs.data() + slice.rowRuns[row];
        end = slice.runs.data() + slice.rowRuns[row + 1];
    }
    bool empty() const { return runs == end; }
    int first() const { return int(runs->begin) - shift - 1; }
    int last() const { return int(runs->end) - shift - 1; }
    Tap<Sample> tap() const { return {samples + runs->offset - runs->begin, right, left}; }
    /// Steps past the runs that end before pixel @a p.
    void skipTo(int p) {
        while (runs != end && last() < p) ++runs;
    }
    /// Where a segment starting at or before the current run ends: with it, or just before it.
    int segmentEnd(bool inside) const {
        if (empty()) return INT32_MAX;
        return inside ? last() : first() - 1;
    }
};

using Ints8 = int __attribute__((vector_size(32)));

/// Eight codes from @a codes on, as floats. (GCC converts them half a register at a time.)
__attribute__((target("avx2"), always_inline)) inline Floats8 eightCodes(const std::uint16_t* codes) {
    const __m128i bits = _mm_loadu_si128(reinterpret_cast<const __m128i*>(codes));
    return (Floats8)_mm256_cvtepi32_ps(_mm256_cvtepu16_epi32(bits));
}

/// The table entries of eight neighbouring pixels from the taps' @a column on:
/// ValueLight::Lookup's levels, in the same order of operations (so the same
/// floats), and ValueLevels::kCount for a dark one.
template <std::size_t TapCount>
__attribute__((target("avx2"), always_inline)) inline Ints8 eightLevels(
    const std::array<Tap<std::uint16_t>, TapCount>& taps, int column, ValueLight::Lookup lookup) {
    Floats8 sum{};
    for (std::size_t t = 0; t < TapCount; ++t) {
        // Half a kilobyte ahead along the row: reused chest frames ran faster with it
        // (docs/benchmarks.md, "Render speed").
        __builtin_prefetch(taps[t].columns + column + 256);
        const Floats8 tap = taps[t].right * eightCodes(taps[t].columns + column) +
                            taps[t].left * eightCodes(taps[t].columns + column + 1);
        sum = t == 0 ? tap : sum + tap;
    }
    const Floats8 level = sum + lookup.firstLevel;
    // ValueLevels::nearest, lane by lane (NaN too goes to 0).
    constexpr float kLast = float(ValueLevels::kCount - 1);
    Floats8 rounded = level + 0.5f;
    rounded = rounded > 0.0f ? rounded : Floats8{};
    rounded = rounded < kLast ? rounded : Floats8{} + kLast;
    return level < lookup.darkBelow ? Ints8{} + ValueLevels::kCount : __builtin_convertvector(rounded, Ints8);
}

/// The light of eight table entries, a register per channel.
struct EightLights {
    Floats8 red, green, blue, opacity;
};

/// Two table entries, @a lo and @a hi bytes into @a table, in one register.
__attribute__((target("avx2"), always_inline)) inline __m256 twoEntries(const char* table, int lo, int hi) {
    const __m128 low = _mm_load_ps(reinterpret_cast<const float*>(table + lo));
    const __m128 high = _mm_load_ps(reinterpret_cast<const float*>(table + hi));
    return _mm256_insertf128_ps(_mm256_castps128_ps256(low), high, 1);
}

/// Table @a light's entries at eight @a levels, transposed from entries side by side.
__attribute__((target("avx2"), always_inline)) inline EightLights eightLights(const Floats4* light, Ints8 levels) {
    // Byte offsets read back one by one: extracting lanes takes two instructions each.
    alignas(32) std::int32_t at[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at), (__m256i)(levels * int(sizeof(Floats4))));
    asm("" : "+m"(at));  // else GCC extracts the lanes after all
    const char* table = reinterpret_cast<const char*>(light);
    // Lanes 0 and 4 side by side in one register, 1 and 5 in the next, and so on.
    const __m256 e04 = twoEntries(table, at[0], at[4]), e15 = twoEntries(table, at[1], at[5]);
    const __m256 e26 = twoEntries(table, at[2], at[6]), e37 = twoEntries(table, at[3], at[7]);
    const __m256 rg01 = _mm256_unpacklo_ps(e04, e15), ba01 = _mm256_unpackhi_ps(e04, e15);  // r0 r1 g0 g1 | r4 r5 g4 g5
    const __m256 rg23 = _mm256_unpacklo_ps(e26, e37), ba23 = _mm256_unpackhi_ps(e26, e37);
    return {(Floats8)_mm256_shuffle_ps(rg01, rg23, 0x44), (Floats8)_mm256_shuffle_ps(rg01, rg23, 0xEE),
            (Floats8)_mm256_shuffle_ps(ba01, ba23, 0x44), (Floats8)_mm256_shuffle_ps(ba01, ba23, 0xEE)};
}

/// Eight floats from @a at on, and back.
__attribute__((target("avx2"), always_inline)) inline Floats8 loadEight(const float* at) {
    return reinterpret_cast<const Unaligned<Floats8>*>(at)->values;
}
__attribute__((target("avx2"), always_inline)) inline void storeEight(float* at, Floats8 values) {
    reinterpret_cast<Unaligned<Floats8>*>(at)->values = values;
}

/// The light that the taps resample for pixels [@a p, @a p + 8), but for the first
/// @a done, which take nothing.
template <std::size_t TapCount>
__attribute__((target("avx2"), always_inline)) inline EightLights lightOfEight(
    const std::array<Tap<std::uint16_t>, TapCount>& taps, int p, int done, int shift, ValueLight::Lookup lookup) {
    const Ints8 lanes{0, 1, 2, 3, 4, 5, 6, 7};
    const Ints8 levels = lanes < done ? Ints8{} + ValueLevels::kCount : eightLevels(taps, p + shift, lookup);
    return eightLights(lookup.light, levels);
}

/// Adds @a light behind pixels [@a p, @a p + 8). Those closed already take nothing
/// and keep their value, as the one-pixel loop's links leave them (a pixel is
/// closed once its opacity reaches @a termination); those that reach it now close.
__attribute__((target("avx2"), always_inline)) inline void compositeEight(const EightLights& light, int p,
                                                                          float termination, PlanarRow row,
                                                                          OpenPixels& open) {
    float* const opacity = row.channel(3) + p;
    const Floats8 alpha = loadEight(opacity);
    const auto isOpen = alpha < termination;
    // A closed pixel's channels gain light x 0, which leaves them as they are.
    const Floats8 clear = isOpen ? 1.0f - alpha : Floats8{};
    const Floats8* channels[3] = {&light.red, &light.green, &light.blue};
    for (int c = 0; c < 3; ++c) {
        float* const at = row.channel(c) + p;
        storeEight(at, loadEight(at) + clear * *channels[c]);
    }
    const Floats8 composited = alpha + clear * light.opacity;
    storeEight(opacity, composited);
    unsigned closing = unsigned(_mm256_movemask_ps((__m256)(isOpen & (composited >= termination))));
    for (; closing != 0; closing &= closing - 1) open.close(p + __builtin_ctz(closing));
}

/// Composites the open pixels of [@a p, @a last] eight at a time, and returns the
/// first pixel left: one function around the whole loop, so that its constants
/// stay in registers.
/// - Each eight's light is resampled before the eight before it is composited, so
///   that the two chains of dependent instructions overlap: chest frames ran faster
///   than where the processor was left to overlap them (docs/benchmarks.md,
///   "Render speed"). (The next
///   open pixel can be found first: closing pixels changes only their own links.)
/// - The last few go as the eight that end at @a last, where the row has eight
///   pixels: one at a time, each cost about as much as eight (a branch on its
///   darkness that the processor mispredicts). That eight's taps may read up to
///   seven samples before the stretch: kStoredMargin keeps them within the slice.
template <std::size_t TapCount>
__attribute__((target("avx2"))) int compositeEights(const std::array<Tap<std::uint16_t>, TapCount>& taps, int p,
                                                    int last, int shift, ValueLight::Lookup lookup, float termination,
                                                    PlanarRow row, OpenPixels& open) {
    if (p + 7 <= last) {
        EightLights light = lightOfEight(taps, p, 0, shift, lookup);
        for (bool more = true; more;) {
            const int next = open.next(p + 8);
            more = next + 7 <= last;
            EightLights following{};
            if (more) following = lightOfEight(taps, next, 0, shift, lookup);
            compositeEight(light, p, termination, row, open);
            p = next;
            light = following;
        }
    }
    if (p > last || last < 7) return p;
    compositeEight(lightOfEight(taps, last - 7, p - (last - 7), shift, lookup), last - 7, termination, row, open);
    return last + 1;
}

/// How one frame composites: the light a resampled sample adds over the oblique
/// path (ClassifiedLight or ValueLight), and where a pixel stops.
template <typename Light>
struct Compositing {
    const Light& light;
    float terminationOpacity;
    CompositeLanes lanes;

    /// Composites the open pixels of [first, last] of an intermediate row, each
    /// taking the sum of @a taps at its column, pixel + shift.
    template <typename... Taps>
    void pixels(OpenPixels& open, RayEnds ends, const ValueCoding& coding, typename Light::Row row, int first, int last,
                int shift, Taps... taps) const {
        const float termination = terminationOpacity;  // a local: pixel stores cannot change it
        auto lookup = light.lookup(ends, coding);
        int p = open.next(first);
        if constexpr (std::is_same_v<Light, ValueLight>) {
            // Eight pixels at a time where the processor has AVX2: one at a time spent
            // most of its instructions moving two codes and one pixel into place.
            // (Without AVX2, GCC converts 16-bit codes one by one, and lanes are slower.)
            if (lanes == CompositeLanes::Best && processorHasAvx2()) {
                p = compositeEights(std::array{taps...}, p, last, shift, lookup, termination, row, open);
            }
        }
        for (; p <= last; p = open.next(p + 1)) {
            const auto sum = (taps(p + shift) + ...);
            if (lookup.dark(p, sum)) continue;  // what is not dark may still add nothing, harmlessly
            row.add(p, lookup(sum), termination, open);
        }
    }
};

/// Rows composited together, slice by slice.
constexpr int kBandRows = 16;

/// One intermediate row, composited front to back slice by slice.
class RowCompositor {
public:
    void reset(int width) {
        mWidth = width;
        mOpen.reset(width);
        mLast.assign(width, RayEnd{});
        mReached = {};
    }
    bool finished() { return mOpen.next(0) >= mWidth; }
    /// The pixels that the slices added so far reached.
    PixelSpan reached() const { return mReached; }

    /// Composites @a slice's classified samples over @a pixels: slice rows @a row
    /// (upper) and row + 1 (lower), sheared by @a shear. A row without a run adds
    /// nothing. @a n counts the slices composited before this one.
    void add(const Slice& slice, int n, int row, int sliceHeight, const SliceShear& shear,
             const Compositing<ClassifiedLight>& compositing, InterleavedRow pixels) {
        const RayEnds ends = endsAt(n);
        ShearedRuns<StackSample> upper(slice, row, sliceHeight, shear.shift, shear.upperLeft, shear.upperRight);
        ShearedRuns<StackSample> lower(slice, row + 1, sliceHeight, shear.shift, shear.lowerLeft, shear.lowerRight);
        // Walk both rows' runs left to right, in segments that one row, or both, reach.
        for (int p = INT32_MIN;;) {
            upper.skipTo(p);
            lower.skipTo(p);
            if (upper.empty() && lower.empty()) break;
            p = std::min(upper.empty() ? INT32_MAX : std::max(p, upper.first()),
                         lower.empty() ? INT32_MAX : std::max(p, lower.first()));
            const bool inUpper = !upper.empty() && upper.first() <= p, inLower = !lower.empty() && lower.first() <= p;
            const int last = std::min(upper.segmentEnd(inUpper), lower.segmentEnd(inLower));
            if (inUpper && inLower) {
                composite(compositing, ends, slice.coding, pixels, p, last, shear, upper.tap(), lower.tap());
            } else if (inUpper) {
                composite(compositing, ends, slice.coding, pixels, p, last, shear, upper.tap());
            } else {
                composite(compositing, ends, slice.coding, pixels, p, last, shear, lower.tap());
            }
            p = last + 1;
        }
    }

    /// The same for a slice of values (ValueLight, SegmentLight or ColourLight). A
    /// value needs both rows, unless one weighs nothing: where either has no run,
    /// every value lies in cells that cannot be seen, nor can the stretches of rays
    /// through them (see SliceStack).
    template <typename Light>
    void add(const Slice& slice, int n, int row, int sliceHeight, const SliceShear& shear,
             const Compositing<Light>& compositing, typename Light::Row pixels) {
        using Sample = typename Light::Sample;
        const RayEnds ends = endsAt(n);
        const auto unit = Light::unitOf(slice.coding);
        ShearedRuns<Sample> upper(slice, row, sliceHeight, shear.shift, shear.upperLeft, shear.upperRight, unit);
        ShearedRuns<Sample> lower(slice, row + 1, sliceHeight, shear.shift, shear.lowerLeft, shear.lowerRight, unit);
        const ValueCoding& coding = slice.coding;
        if (shear.lowerLeft + shear.lowerRight == 0.0f)
            return addAlone(upper, ends, coding, shear, compositing, pixels);
        if (shear.upperLeft + shear.upperRight == 0.0f)
            return addAlone(lower, ends, coding, shear, compositing, pixels);
        // Walk the stretches that both rows' runs reach, left to right.
        for (int p = INT32_MIN;;) {
            upper.skipTo(p);
            lower.skipTo(p);
            if (upper.empty() || lower.empty()) break;
            const int first = std::max(upper.first(), lower.first()), last = std::min(upper.last(), lower.last());
            if (first <= last) {
                composite(compositing, ends, slice.coding, pixels, first, last, shear, upper.tap(), lower.tap());
            }
            p = last + 1;
        }
    }

private:
    /// One slice row's values, where the other row weighs nothing.
    template <typename Light>
    void addAlone(ShearedRuns<typename Light::Sample> only, RayEnds ends, const ValueCoding& coding,
                  const SliceShear& shear, const Compositing<Light>& compositing, typename Light::Row pixels) {
        for (; !only.empty(); ++only.runs) {
            composite(compositing, ends, coding, pixels, only.first(), only.last(), shear, only.tap());
        }
    }

    /// Composites pixels [first, last] within the volume's faces, noting that they were reached.
    template <typename Light, typename... Taps>
    void composite(const Compositing<Light>& compositing, RayEnds ends, const ValueCoding& coding,
                   typename Light::Row pixels, int first, int last, const SliceShear& shear, Taps... taps) {
        first = std::max(first, shear.firstPixel);
        last = std::min(last, shear.lastPixel);
        if (first > last) return;
        mReached = {std::min(mReached.first, first), std::max(mReached.last, last)};
        compositing.pixels(mOpen, ends, coding, pixels, first, last, shear.shift, taps...);
    }

    RayEnds endsAt(int n) { return {mLast.data(), std::uint32_t(n) + 2}; }

    int mWidth = 0;
    OpenPixels mOpen;
    std::vector<RayEnd> mLast;  ///< each pixel's
    PixelSpan mReached;
};

}  // namespace

std::string ShearWarpSettings::validate() const {
    // Below a twentieth of a voxel the stack would hold thousands of slices per voxel row.
    if (!(sliceSpacingVoxels >= 0.05) || sliceSpacingVoxels > 64.0)
        return "`slice_spacing` must be in [0.05, 64] voxels";
    if (!(reuseAngleDeg >= 0.0 && reuseAngleDeg <= 60.0)) return "`reuse_angle` must be between 0 and 60 degrees";
    if (!(terminationOpacity > 0.0f && terminationOpacity <= 1.0f)) return "`termination` must be in (0, 1]";
    if (!(supersampling >= 1.0 && supersampling <= 4.0)) return "`supersample` must be in [1, 4]";
    return {};
}

Vec3d ShearWarpSettings::stackNormalFor(const Vec3d& direction) const {
    if (stacks == StackOrientation::View) return direction.unit();
    // Ties go to the first axis, so that a view at exactly 45 degrees has one stack.
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
        if (std::abs(direction[a]) > std::abs(direction[axis])) axis = a;
    }
    return Vec3d(axis == 0, axis == 1, axis == 2);
}

SegmentViews ShearWarpSettings::segmentViews() const {
    const double axisToDiagonalDeg = std::acos(1.0 / std::sqrt(3.0)) * 180.0 / M_PI;
    return {classification, stacks == StackOrientation::View ? reuseAngleDeg : axisToDiagonalDeg};
}

bool ShearWarpSettings::serves(const Vec3d& normal, const Vec3d& direction) const {
    if (stacks == StackOrientation::Axes) return normal == stackNormalFor(direction);
    return angleToStackDeg(direction, normal) <= reuseAngleDeg;
}

double angleToStackDeg(const Vec3d& direction, const Vec3d& normal) {
    return angleBetweenDeg(direction, direction.dot(normal) < 0.0 ? -normal : normal);
}

namespace {

/// Where a band of rows is composited: in the intermediate image itself, RGBA side
/// by side, or in planes that are interleaved into it once the band is done (a
/// pass over the band, little beside compositing it slice by slice).
template <typename Row>
class BandPixels;

template <>
class BandPixels<InterleavedRow> {
public:
    BandPixels(IntermediateImage& out, int firstRow, int rowCount)
        : mFirst(out.rgba.data() + std::size_t(firstRow) * out.width * 4), mWidth(out.width) {
        std::fill(mFirst, mFirst + std::size_t(rowCount) * mWidth * 4, 0.0f);
    }
    InterleavedRow row(int r) const { return {mFirst + std::size_t(r) * mWidth * 4}; }
    void finish() const {}

private:
    float* mFirst;
    int mWidth;
};

template <>
class BandPixels<PlanarRow> {
public:
    BandPixels(IntermediateImage& out, int firstRow, int rowCount)
        : mOut(out), mFirstRow(firstRow), mRowCount(rowCount) {
        planes().assign(std::size_t(rowCount) * out.width * 4, 0.0f);
    }
    PlanarRow row(int r) const { return {planes().data() + std::size_t(r) * mOut.width * 4, mOut.width}; }
    void finish() const {
        for (int r = 0; r < mRowCount; ++r) {
            const PlanarRow from = row(r);
            float* to = mOut.rgba.data() + std::size_t(mFirstRow + r) * mOut.width * 4;
            for (int p = 0; p < mOut.width; ++p) {
                for (int c = 0; c < 4; ++c) to[std::size_t(p) * 4 + c] = from.channel(c)[p];
            }
        }
    }

private:
    /// Each thread's, kept from band to band.
    static std::vector<float>& planes() {
        thread_local std::vector<float> kept;
        return kept;
    }
    IntermediateImage& mOut;
    int mFirstRow, mRowCount;
};

/// Composites every slice of @a stack into @a out, sheared by @a shears, front to
/// back: from the last slice first when @a backwards.
template <typename Light>
void compositeBands(const SliceStack& stack, const std::vector<SliceShear>& shears, bool backwards,
                    const Compositing<Light>& compositing, IntermediateImage& out) {
    const StackGeometry& g = stack.geometry();
    // Bands of rows, each walked slice by slice: a band's rows of one slice lie
    // together in memory, so the stack streams in order instead of hopping between
    // slices once per row.
    const int bands = (out.height + kBandRows - 1) / kBandRows;
    tbb::parallel_for(0, bands, [&](int band) {
        thread_local RowCompositor rows[kBandRows];
        const int firstRow = band * kBandRows, rowCount = std::min(kBandRows, out.height - firstRow);
        for (int r = 0; r < rowCount; ++r) rows[r].reset(out.width);
        BandPixels<typename Light::Row> pixels(out, firstRow, rowCount);
        for (int n = 0; n < g.slices; ++n) {
            const int k = backwards ? g.slices - 1 - n : n;
            const Slice& slice = stack.slices()[k];
            bool open = false;
            for (int r = 0; r < rowCount; ++r) {
                const int row = firstRow + r;
                if (rows[r].finished()) continue;
                open = true;
                // Rays beyond the volume's faces cross nothing, whatever the
                // background's row beyond resamples to.
                const double sliceRow = row + shears[k].row;
                if (sliceRow < g.firstRowInside - 1e-6 || sliceRow > g.lastRowInside + 1e-6) continue;
                rows[r].add(slice, n, row + shears[k].rowOffset, g.height, shears[k], compositing, pixels.row(r));
            }
            if (!open) break;
        }
        pixels.finish();
        for (int r = 0; r < rowCount; ++r) out.reached[firstRow + r] = rows[r].reached();
    });
}

/// @a memory: storage for the intermediate image, of any size and content.
IntermediateImage compositeSlices(const SliceStack& stack, const Vec3d& direction, const ShearWarpSettings& settings,
                                  std::vector<float> memory) {
    const float terminationOpacity = settings.terminationOpacity;
    const CompositeLanes lanes = settings.compositeLanes;
    const StackGeometry& g = stack.geometry();
    const double dn = direction.dot(g.normal);
    // Moving one slice back shifts the ray this far across the slices, in samples.
    const double shiftX = direction.dot(g.e1) / dn * g.sliceMm / g.sampleMm[0];
    const double shiftY = direction.dot(g.e2) / dn * g.sliceMm / g.sampleMm[1];
    const double lastX = shiftX * (g.slices - 1), lastY = shiftY * (g.slices - 1);
    IntermediateImage out;
    // The margins keep every pixel a sample reaches inside the image, whatever the shear.
    out.originX = int(std::floor(std::min(0.0, -lastX))) - 1;
    out.originY = int(std::floor(std::min(0.0, -lastY))) - 1;
    out.width = int(std::ceil(std::max(0.0, -lastX))) + g.width + 1 - out.originX;
    out.height = int(std::ceil(std::max(0.0, -lastY))) + g.height + 1 - out.originY;
    // Each band clears its own rows, while they are in its core's cache.
    out.rgba = std::move(memory);
    out.rgba.resize(std::size_t(out.width) * out.height * 4);
    out.reached.resize(out.height);
    std::vector<SliceShear> shears(g.slices);
    for (int k = 0; k < g.slices; ++k) shears[k] = shearOf(g, k, shiftX, shiftY, out.originX, out.originY);
    // A view from behind the stack meets its slices last to first.
    const bool backwards = dn < 0.0;
    // The path through one slice is 1 / cos(angle) slice spacings long.
    const double obliquity = 1.0 / std::abs(dn);
    const ValueLevels* levels = stack.valueLevels();
    if (stack.content() == StackContent::Colours) {
        const ColourLight light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<ColourLight>{light, terminationOpacity, lanes}, out);
    } else if (levels && stack.classification() == Classification::Segments) {
        const SegmentLight light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<SegmentLight>{light, terminationOpacity, lanes}, out);
    } else if (levels) {
        const ValueLight light(*levels, obliquity);
        compositeBands(stack, shears, backwards, Compositing<ValueLight>{light, terminationOpacity, lanes}, out);
    } else {
        const ObliquityTable oblique(obliquity);
        const ClassifiedLight light{oblique};
        compositeBands(stack, shears, backwards, Compositing<ClassifiedLight>{light, terminationOpacity, lanes}, out);
    }
    return out;
}

/// Where the camera's pixels meet the front slice of the stack, on @a intermediate.
IntermediateMap intermediateMap(const StackGeometry& g, const OrthoCamera& camera,
                                const IntermediateImage& intermediate) {
    const double dn = camera.direction.dot(g.normal);
    const auto onFront = [&](double x, double y) {
        // Follow the pixel's ray to the front slice; its position there, in samples.
        const Vec3d p = camera.pixelPoint(x, y);
        const Vec3d q = p + camera.direction * (g.normal.dot(g.origin - p) / dn) - g.origin;
        return openvdb::Vec2d(q.dot(g.e1) / g.sampleMm[0] - intermediate.originX,
                              q.dot(g.e2) / g.sampleMm[1] - intermediate.originY);
    };
    const openvdb::Vec2d origin = onFront(0, 0), alongX = onFront(1, 0) - origin, alongY = onFront(0, 1) - origin;
    return {origin[0], alongX[0], alongY[0], origin[1], alongX[1], alongY[1]};
}

}  // namespace

ShearWarpRenderer::ShearWarpRenderer(const RenderVolume& volume, const Classifier& classifier,
                                     const ShearWarpSettings& settings)
    : ShearWarpRenderer(std::vector<StackLayer>{{&volume, classifier}}, settings) {}

ShearWarpRenderer::ShearWarpRenderer(std::vector<StackLayer> layers, const ShearWarpSettings& settings)
    : mLayers(std::move(layers)), mSettings(settings) {}

Framebuffer ShearWarpRenderer::render(const OrthoCamera& camera, FrameStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    FrameStats frame;
    frame.index = mFrames++;
    auto serving = std::find_if(mStacks.begin(), mStacks.end(), [&](const std::unique_ptr<SliceStack>& stack) {
        return mSettings.serves(stack->geometry().normal, camera.direction);
    });
    frame.reused = serving != mStacks.end();
    if (!frame.reused) {
        // A view stack serves only its cone: the next one replaces it.
        if (mSettings.stacks == StackOrientation::View) mStacks.clear();
        mStacks.push_back(std::make_unique<SliceStack>(
            mLayers, mSettings.stackNormalFor(camera.direction), mSettings.sliceSpacingVoxels,
            mSettings.sampleMmFor(camera, *mLayers.front().volume), ProgressFn{}, nullptr, StackSampling::Voxels,
            mSettings.segmentViews()));
        serving = std::prev(mStacks.end());
        frame.buildMs = millisecondsSince(start);
        frame.gaussiansTouched = (*serving)->gaussiansTouched();
    }
    Framebuffer image = mFramer.frame(**serving, camera, mSettings, frame);
    frame.totalMs = millisecondsSince(start);
    if (stats) *stats = frame;
    return image;
}

Framebuffer ShearWarpFramer::frame(const SliceStack& stack, const OrthoCamera& camera,
                                   const ShearWarpSettings& settings, FrameStats& stats) {
    const auto composited = std::chrono::steady_clock::now();
    IntermediateImage intermediate = compositeSlices(stack, camera.direction, settings, std::move(mIntermediate));
    stats.compositeMs = millisecondsSince(composited);

    const auto warped = std::chrono::steady_clock::now();
    Framebuffer image =
        warpToImage(intermediate, intermediateMap(stack.geometry(), camera, intermediate), camera.width, camera.height);
    stats.warpMs = millisecondsSince(warped);
    mIntermediate = std::move(intermediate.rgba);
    return image;
}

}  // namespace gvr
