/// @file BoundSearch.h
/// @brief `gvr fit --ratio R --max-error auto`: the smallest error bound whose asset
/// fits a byte budget, found in a few encodes of the residual layer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>

namespace gvr {

/// The bounds a search may try, rising: whole stored samples for integer data (so
/// that each is a different quantisation), else floats 2 % apart.
class BoundLadder {
public:
    /// 0, s, 2s, ... up to the first multiple of @a sampleStep at least @a span, each
    /// but 0 raised by @a rounding: what rounding samples to float may add to their
    /// difference, so that a bound of whole samples is not missed by a hair.
    static BoundLadder wholeSamples(double sampleStep, double span, double rounding = 0.0);
    /// @a span * 1e-7 up to @a span (the data range: one quantisation step holds it all).
    static BoundLadder values(double span);

    std::size_t size() const { return mSize; }
    double bound(std::size_t index) const;
    /// Where @a index sits on a log scale of the bound, along which a layer's bytes fall
    /// about linearly (a bit a voxel for each halving).
    double position(std::size_t index) const;
    /// The index whose position is nearest @a position.
    std::size_t indexAt(double position) const;

private:
    BoundLadder(bool wholeSamples, double base, std::size_t size, double rounding)
        : mWholeSamples(wholeSamples), mBase(base), mSize(size), mRounding(rounding) {}
    bool mWholeSamples;
    double mBase;  ///< the sample step, or the smallest bound
    std::size_t mSize;
    double mRounding;
};

struct SearchedBound {
    double bound = 0.0;
    std::uint64_t bytes = 0;
    int encodes = 0;  ///< how many bounds were tried
};

/// The smallest bound of @a ladder whose @a bytesAt (falling as the bound rises) is
/// at most @a maxBytes; none when even the largest is over. Each step interpolates the
/// bytes along the ladder's positions and falls back to halving the bracket when that gained too
/// little, so it takes a few encodes and never more than about twice a bisection's.
std::optional<SearchedBound> smallestBoundWithin(const BoundLadder& ladder, std::uint64_t maxBytes,
                                                 const std::function<std::uint64_t(double bound)>& bytesAt);

}  // namespace gvr
