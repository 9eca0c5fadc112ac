#include "render/Warp.h"

#include "pipeline/FastExp.h"

#include <openvdb/math/Vec2.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gvr {

namespace {

Floats4 load4(const float* values) {
    Floats4 out;
    std::memcpy(&out, values, sizeof out);
    return out;
}

/// The intermediate image, bilinearly, at (u, v), which must lie inside its samples.
Floats4 bilinearInside(const IntermediateImage& image, float u, float v) {
    const int i = int(u), j = int(v);
    const float fu = u - float(i), fv = v - float(j);
    const float* a = image.rgba.data() + (std::size_t(j) * image.width + i) * 4;
    const float* b = a + std::size_t(image.width) * 4;
    const Floats4 top = (1 - fu) * load4(a) + fu * load4(a + 4);
    const Floats4 bottom = (1 - fu) * load4(b) + fu * load4(b + 4);
    return (1 - fv) * top + fv * bottom;
}

/// The same anywhere: transparent beyond the samples.
Floats4 bilinear(const IntermediateImage& image, double u, double v) {
    // The comparisons are false for NaN, and u < width - 1 keeps i + 1 inside.
    if (!(u >= 0.0 && v >= 0.0 && u < image.width - 1 && v < image.height - 1)) return Floats4{};
    return bilinearInside(image, float(u), float(v));
}

/// How an image pixel averages its footprint on the intermediate image: taps x taps
/// bilinear taps spread evenly over it, as the anti-aliased ray marcher spreads its
/// rays over the pixel. At least two a side, and enough that neighbouring taps lie
/// about one intermediate pixel apart.
class FootprintFilter {
public:
    FootprintFilter(const IntermediateMap& map, const IntermediateImage& image) : mImage(image) {
        const double footprint = std::max(std::abs(map.dux) + std::abs(map.duy), std::abs(map.dvx) + std::abs(map.dvy));
        const int taps = std::clamp(int(std::ceil(footprint)), 2, 4);
        double reachU = 0.0, reachV = 0.0;
        for (int ty = 0; ty < taps; ++ty) {
            for (int tx = 0; tx < taps; ++tx) {
                const double x = (tx + 0.5) / taps - 0.5, y = (ty + 0.5) / taps - 0.5;
                const float du = float(x * map.dux + y * map.duy), dv = float(x * map.dvx + y * map.dvy);
                mOffsets.push_back({du, dv});
                reachU = std::max(reachU, double(std::abs(du)));
                reachV = std::max(reachV, double(std::abs(dv)));
            }
        }
        mReach = {reachU, reachV};
        mWeight = 1.0f / float(mOffsets.size());
        // Taps in floats are faster than in doubles: the margin covers their
        // rounding (an ulp at 65536 is 0.004), so that i + 1 stays inside.
        const double margin = 1e-3 + 1e-6 * std::max(image.width, image.height);
        mInsideLo = {reachU, reachV};
        mInsideHi = {image.width - 1 - margin - reachU, image.height - 1 - margin - reachV};
    }

    /// The pixel whose centre falls at (u, v) on the intermediate image.
    Floats4 operator()(double u, double v) const {
        Floats4 sum{};
        if (u >= mInsideLo[0] && v >= mInsideLo[1] && u < mInsideHi[0] && v < mInsideHi[1]) {
            for (const Offset& o : mOffsets) sum += bilinearInside(mImage, float(u) + o.du, float(v) + o.dv);
        } else {
            for (const Offset& o : mOffsets) sum += bilinear(mImage, u + o.du, v + o.dv);
        }
        return sum * mWeight;
    }
    /// How far from a pixel's centre, in intermediate pixels, its taps fall.
    openvdb::Vec2d reach() const { return mReach; }

private:
    struct Offset {
        float du, dv;
    };
    const IntermediateImage& mImage;
    std::vector<Offset> mOffsets;
    float mWeight = 1.0f;
    openvdb::Vec2d mInsideLo, mInsideHi;  ///< where every tap of a pixel's centre falls inside the samples
    openvdb::Vec2d mReach;
};

/// Where on the intermediate image an image pixel's taps may find light: tiles of
/// it that the rows' reached spans touch, widened by the taps' reach. Most of a
/// frame often lies beyond the volume, and its pixels need not read their taps.
class LitTiles {
public:
    LitTiles(const IntermediateImage& image, openvdb::Vec2d reach)
        // A tap reads texels up to reach + 1 from the centre: that many tiles away, rounded up.
        : mMarginU(int((reach[0] + 1.0) / kTile) + 1),
          mMarginV(int((reach[1] + 1.0) / kTile) + 1),
          mColumns((image.width + kTile - 1) / kTile + 2 * mMarginU),
          mRows((image.height + kTile - 1) / kTile + 2 * mMarginV),
          mLit(std::size_t(mColumns) * mRows, 0) {
        for (int j = 0; j < image.height; ++j) {
            const PixelSpan span = image.reached[j];
            if (span.empty()) continue;
            const int last = std::min(span.last, image.width - 1) / kTile;
            for (int column = std::max(span.first, 0) / kTile; column <= last; ++column) {
                mLit[index(j / kTile + mMarginV, column + mMarginU)] = 1;
            }
        }
        widenByMargins();
        findBounds();
    }

    /// The image pixels of row @a y outside which none may read light: where the
    /// row's line on the intermediate image crosses the lit tiles' bounding box (a
    /// pixel to spare each side for rounding), within [0, @a width).
    PixelSpan columnsOfRow(const IntermediateMap& map, int y, int width) const {
        if (mBoundsLo[0] > mBoundsHi[0]) return {};
        double first = 0.0, last = width - 1.0;
        const double along[2] = {map.dux, map.dvx}, start[2] = {map.u0 + y * map.duy, map.v0 + y * map.dvy};
        for (int axis = 0; axis < 2; ++axis) {
            if (along[axis] == 0.0) {
                if (!(start[axis] >= mBoundsLo[axis] && start[axis] <= mBoundsHi[axis])) return {};
                continue;
            }
            const double a = (mBoundsLo[axis] - start[axis]) / along[axis];
            const double b = (mBoundsHi[axis] - start[axis]) / along[axis];
            first = std::max(first, std::min(a, b) - 1.0);
            last = std::min(last, std::max(a, b) + 1.0);
        }
        // A bound that is not a number drops out of max and min: every pixel is then asked.
        if (first > last) return {};
        return {int(std::floor(first)), int(std::ceil(last))};
    }

    /// Whether a pixel whose centre falls at (u, v) may read any light.
    bool mayLight(double u, double v) const {
        const double column = u * (1.0 / kTile) + mMarginU, row = v * (1.0 / kTile) + mMarginV;
        // False for NaN too, as the filter finds nothing there. Past it, truncation is floor.
        if (!(column >= 0.0 && row >= 0.0 && column < mColumns && row < mRows)) return false;
        return lit(int(row), int(column));
    }

private:
    static constexpr int kTile = 4;

    /// Lights every tile within the margins of a lit one, first along rows, then columns.
    void widenByMargins() {
        std::vector<char> alongRows(mLit.size(), 0);
        for (int row = 0; row < mRows; ++row) {
            for (int column = 0; column < mColumns; ++column) {
                if (!lit(row, column)) continue;
                const int to = std::min(mColumns - 1, column + mMarginU);
                for (int c = std::max(0, column - mMarginU); c <= to; ++c) alongRows[index(row, c)] = 1;
            }
        }
        for (int row = 0; row < mRows; ++row) {
            for (int column = 0; column < mColumns; ++column) {
                if (!alongRows[index(row, column)]) continue;
                const int to = std::min(mRows - 1, row + mMarginV);
                for (int r = std::max(0, row - mMarginV); r <= to; ++r) mLit[index(r, column)] = 1;
            }
        }
    }
    /// The intermediate pixels that the lit tiles cover: [lo, hi] along u and v (lo > hi when none is lit).
    void findBounds() {
        mBoundsLo = openvdb::Vec2d(INFINITY);
        mBoundsHi = openvdb::Vec2d(-INFINITY);
        for (int row = 0; row < mRows; ++row) {
            for (int column = 0; column < mColumns; ++column) {
                if (!lit(row, column)) continue;
                const openvdb::Vec2d lo((column - mMarginU) * kTile, (row - mMarginV) * kTile);
                mBoundsLo = minComponent(mBoundsLo, lo);
                mBoundsHi = maxComponent(mBoundsHi, lo + openvdb::Vec2d(kTile));
            }
        }
    }
    std::size_t index(int row, int column) const { return std::size_t(row) * mColumns + column; }
    bool lit(int row, int column) const { return mLit[index(row, column)]; }

    int mMarginU, mMarginV, mColumns, mRows;
    std::vector<char> mLit;  ///< per tile, rows of columns
    openvdb::Vec2d mBoundsLo, mBoundsHi;
};

}  // namespace

Framebuffer warpToImage(const IntermediateImage& intermediate, const IntermediateMap& map, int width, int height) {
    Framebuffer image(width, height);
    const FootprintFilter footprint(map, intermediate);
    const LitTiles lit(intermediate, footprint.reach());
    tbb::parallel_for(0, height, [&](int y) {
        const PixelSpan columns = lit.columnsOfRow(map, y, width);
        for (int x = columns.first; x <= columns.last; ++x) {
            const double u = map.u0 + x * map.dux + y * map.duy, v = map.v0 + x * map.dvx + y * map.dvy;
            if (!lit.mayLight(u, v)) continue;  // the image starts transparent
            const Floats4 pixel = footprint(u, v);
            std::memcpy(image.pixel(x, y), &pixel, sizeof pixel);
        }
    });
    return image;
}

}  // namespace gvr
