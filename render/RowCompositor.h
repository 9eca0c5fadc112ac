/// @file RowCompositor.h
/// @brief Slices composited front to back into the intermediate image: a row at a time,
/// bands of rows in parallel. Internal to the renderer.
#pragma once

#include "render/CompositeKernels.h"
#include "render/Warp.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <climits>

namespace gvr::compositing {

/// How one frame composites: the light a resampled sample adds over the oblique
/// path (ClassifiedLightTable or ValueLightTable), and where a pixel stops.
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
        if constexpr (std::is_same_v<Light, ValueLightTable>) {
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
             const Compositing<ClassifiedLightTable>& compositing, InterleavedRow pixels) {
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

    /// The same for a slice of values (ValueLightTable, SegmentLightTable or ColourLightTable). A
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

}  // namespace gvr::compositing
