#include "workflow/BoundSearch.h"

#include <algorithm>
#include <cmath>

namespace gvr {
namespace {

constexpr double kValueStep = 1.02;      // floats: the search's precision
constexpr double kSmallestShare = 1e-7;  // floats: about a float32's precision over the range

/// One tried bound of a search.
struct Tried {
    std::size_t index;
    std::uint64_t bytes;
};

}  // namespace

BoundLadder BoundLadder::wholeSamples(double sampleStep, double span, double rounding) {
    const double steps = std::ceil(std::max(span, 0.0) / sampleStep);
    return BoundLadder(true, sampleStep, std::size_t(steps) + 1, rounding);
}

BoundLadder BoundLadder::values(double span) {
    const double smallest = span * kSmallestShare;
    return BoundLadder(false, smallest,
                       std::size_t(std::ceil(std::log(1.0 / kSmallestShare) / std::log(kValueStep))) + 1, 0.0);
}

double BoundLadder::bound(std::size_t index) const {
    if (!mWholeSamples) return mBase * std::pow(kValueStep, double(index));
    // k samples' worth, never a hair under it (the layer rounds a bound down to whole samples).
    double bound = double(index) * mBase + (index > 0 ? mRounding : 0.0);
    while (std::floor(bound / mBase) < double(index)) bound = std::nextafter(bound, INFINITY);
    return bound;
}

double BoundLadder::position(std::size_t index) const {
    return mWholeSamples ? std::log(double(index) + 0.5) : double(index);
}

std::size_t BoundLadder::indexAt(double position) const {
    const double index = mWholeSamples ? std::exp(position) - 0.5 : position;
    return std::size_t(std::clamp(std::round(index), 0.0, double(mSize - 1)));
}

std::optional<SearchedBound> smallestBoundWithin(const BoundLadder& ladder, std::uint64_t maxBytes,
                                                 const std::function<std::uint64_t(double)>& bytesAt) {
    int encodes = 0;
    const auto tryIndex = [&](std::size_t index) {
        ++encodes;
        return Tried{index, bytesAt(ladder.bound(index))};
    };
    Tried fits = tryIndex(ladder.size() - 1);
    if (fits.bytes > maxBytes) return std::nullopt;
    if (ladder.size() == 1) return SearchedBound{ladder.bound(0), fits.bytes, encodes};
    Tried over = tryIndex(0);
    if (over.bytes <= maxBytes) return SearchedBound{ladder.bound(0), over.bytes, encodes};

    bool interpolate = true;
    while (fits.index - over.index > 1) {
        const double low = ladder.position(over.index), high = ladder.position(fits.index);
        double guess = 0.5 * (low + high);
        if (interpolate) {
            const double share = double(over.bytes - maxBytes) / double(over.bytes - fits.bytes);
            guess = low + std::clamp(share, 0.0, 1.0) * (high - low);
        }
        const std::size_t index = std::clamp(ladder.indexAt(guess), over.index + 1, fits.index - 1);
        const Tried tried = tryIndex(index);
        (tried.bytes <= maxBytes ? fits : over) = tried;
        // An interpolation that left more than half the bracket is followed by a halving.
        interpolate = !interpolate || ladder.position(fits.index) - ladder.position(over.index) <= 0.5 * (high - low);
    }
    return SearchedBound{ladder.bound(fits.index), fits.bytes, encodes};
}

}  // namespace gvr
