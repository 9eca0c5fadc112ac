/// @file CompositeKernels.h
/// @brief The compositor's inner loops: a slice row's samples loaded and sheared onto
/// the intermediate image (taps), and eight pixels at a time where the processor
/// has AVX2. Internal to the renderer.
#pragma once

#include "render/LightTables.h"

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <array>
#include <cstring>
#include <type_traits>

namespace gvr::compositing {

inline float load(std::uint16_t code) { return code; }

/// Two neighbouring codes as floats, in the two lowest lanes: one load and one
/// conversion, where two scalar ones made reused frames slower than floats
/// (docs/benchmarks.md, "Render speed").
inline Floats4 loadPair(const std::uint16_t* codes) {
#if defined(__SSE2__)
    std::int32_t bits;
    std::memcpy(&bits, codes, sizeof bits);
    return (Floats4)_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_cvtsi32_si128(bits), _mm_setzero_si128()));
#else
    return Floats4{float(codes[0]), float(codes[1]), 0.0f, 0.0f};
#endif
}

inline Floats4 load(const StackSample& sample) {
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

inline SliceShear shearOf(const StackGeometry& g, int k, double shiftX, double shiftY, int originX, int originY) {
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
/// ValueLightTable::Lookup's levels, in the same order of operations (so the same
/// floats), and ValueLevels::kCount for a dark one.
template <std::size_t TapCount>
__attribute__((target("avx2"), always_inline)) inline Ints8 eightLevels(
    const std::array<Tap<std::uint16_t>, TapCount>& taps, int column, ValueLightTable::Lookup lookup) {
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
    const std::array<Tap<std::uint16_t>, TapCount>& taps, int p, int done, int shift, ValueLightTable::Lookup lookup) {
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
__attribute__((target("avx2"))) inline int compositeEights(const std::array<Tap<std::uint16_t>, TapCount>& taps, int p,
                                                           int last, int shift, ValueLightTable::Lookup lookup,
                                                           float termination, PlanarRow row, OpenPixels& open) {
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

}  // namespace gvr::compositing
