#include "Growth.h"

#include "GaussianKernel.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gvr {

std::size_t countAtStage(std::size_t finalCount, int doublings, int stage) {
    const std::size_t divisor = std::size_t(1) << std::clamp(doublings - stage, 0, 30);
    return std::max<std::size_t>((finalCount + divisor - 1) / divisor, std::min<std::size_t>(finalCount, 1));
}

int stageAt(double fraction, int doublings, double share) {
    if (doublings <= 0 || !(fraction < share)) return std::max(doublings, 0);
    return std::clamp(int(fraction / share * doublings), 0, doublings);
}

namespace {

int widestAxis(const float* logScale) {
    return int(std::max_element(logScale, logScale + 3) - logScale);
}

/// Turns Gaussian @a parent into the first half and writes the second half at @a child.
void splitOne(GaussianParameters& params, std::size_t parent, std::size_t child) {
    for (int g = 0; g < kGroupCount; ++g) {
        const ParameterGroup group = ParameterGroup(g);
        std::copy_n(params.at(group, parent), params.width(group), params.at(group, child));
    }
    float* logScale = params.at(kLogScales, parent);
    const int axis = widestAxis(logScale);
    const float sigma = std::exp(logScale[axis]);
    float q[4], rotation[9];
    const float* raw = params.at(kRotations, parent);
    const float norm = std::sqrt(raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2] + raw[3] * raw[3]);
    for (int k = 0; k < 4; ++k) q[k] = norm > 0.0f ? raw[k] / norm : float(k == 0);
    rotationFromQuaternion(q, rotation);
    for (int a = 0; a < 3; ++a) {
        const float offset = 0.5f * sigma * rotation[3 * a + axis];  // column `axis` of R
        params.at(kMeans, parent)[a] -= offset;
        params.at(kMeans, child)[a] += offset;
    }
    const float shrink = std::log(std::sqrt(3.0f) / 2.0f);
    params.at(kLogScales, parent)[axis] += shrink;
    params.at(kLogScales, child)[axis] += shrink;
    // Each half's mass is (sqrt(3)/2) / 2 of the parent's at the same amplitude.
    for (int c = 0; c < params.channels; ++c) {
        params.at(kColours, parent)[c] /= std::sqrt(3.0f);
        params.at(kColours, child)[c] /= std::sqrt(3.0f);
    }
}

}  // namespace

std::size_t splitWidest(GaussianParameters& params, Adam& adam, std::size_t extra) {
    const std::size_t count = params.count();
    extra = std::min(extra, count);
    if (extra == 0) return 0;
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t(0));
    const auto longest = [&](std::size_t i) {
        const float* s = params.at(kLogScales, i);
        return s[widestAxis(s)];
    };
    std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(extra), order.end(),
                      [&](std::size_t a, std::size_t b) { return longest(a) > longest(b) || (longest(a) == longest(b) && a < b); });
    for (int g = 0; g < kGroupCount; ++g) {
        params.values[g].resize((count + extra) * std::size_t(params.width(ParameterGroup(g))));
    }
    for (std::size_t k = 0; k < extra; ++k) splitOne(params, order[k], count + k);
    adam.grow(params.count());
    return extra;
}

}  // namespace gvr
