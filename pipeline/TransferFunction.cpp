#include "pipeline/TransferFunction.h"

#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace gvr {

TransferFunction::TransferFunction(std::vector<TransferPoint> points, const std::string& culprit)
    : mPoints(std::move(points)) {
    if (mPoints.empty()) throw InputError(culprit, "a transfer function needs at least one point");
    for (std::size_t n = 0; n < mPoints.size(); ++n) {
        const TransferPoint& p = mPoints[n];
        const std::string where = "point " + std::to_string(n) + " (value " + std::to_string(p.value) + ")";
        if (!std::isfinite(p.value)) throw InputError(culprit, where + ": the value is not finite");
        if (n > 0 && !(p.value > mPoints[n - 1].value)) {
            throw InputError(culprit, where + ": values must increase from point to point");
        }
        for (float channel : p.rgba) {
            if (!(channel >= 0.0f && channel <= 1.0f)) {
                throw InputError(culprit, where + ": colour and opacity must lie in [0, 1]");
            }
        }
    }
}

double TransferFunction::transparentUpTo() const {
    if (mPoints.front().rgba[3] > 0.0f) return -INFINITY;
    std::size_t last = 0;
    while (last + 1 < mPoints.size() && mPoints[last + 1].rgba[3] == 0.0f) ++last;
    return last + 1 == mPoints.size() ? INFINITY : mPoints[last].value;
}

namespace {

/// Where @a value lies between @a lo and @a hi, as a share in [0, 1]; halved when the
/// span overflows (points near +-DBL_MAX), since halving an exact denormal gap could
/// round it to zero.
double shareBetween(double value, double lo, double hi) {
    const double span = hi - lo;
    if (std::isinf(span)) return (value * 0.5 - lo * 0.5) / (hi * 0.5 - lo * 0.5);
    return (value - lo) / span;
}

}  // namespace

std::array<float, 4> TransferFunction::operator()(double value) const {
    if (!(value > mPoints.front().value)) return mPoints.front().rgba;
    if (value >= mPoints.back().value) return mPoints.back().rgba;
    const auto above = std::upper_bound(mPoints.begin(), mPoints.end(), value,
                                        [](double v, const TransferPoint& p) { return v < p.value; });
    const TransferPoint& lo = *(above - 1);
    const TransferPoint& hi = *above;
    const float t = float(shareBetween(value, lo.value, hi.value));
    std::array<float, 4> out;
    for (int c = 0; c < 4; ++c) out[c] = lo.rgba[c] + t * (hi.rgba[c] - lo.rgba[c]);
    return out;
}

}  // namespace gvr
