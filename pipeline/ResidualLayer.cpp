#include "pipeline/ResidualLayer.h"

#include "pipeline/Block.h"
#include "pipeline/Error.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace gvr {

namespace {

constexpr double kMaxSampleMagnitude = 2147483647.0;  // |k| of an integer domain
constexpr double kMaxPrediction = 1e15;               // integers stay exact in a double well past this

/// The slices [begin, end) of one slab and the volume's shape.
struct Slab {
    int nx, ny, begin, end;
    std::size_t voxels() const { return std::size_t(nx) * ny * (end - begin); }
    std::size_t local(int i, int j, int k) const { return (std::size_t(k - begin) * ny + j) * nx + i; }
};

Slab slabOf(const openvdb::Coord& dims, int s) {
    return {dims.x(), dims.y(), s * kResidualSlabSlices, std::min(dims.z(), (s + 1) * kResidualSlabSlices)};
}

openvdb::Coord blocksOf(const openvdb::Coord& dims) {
    return {(dims.x() + kBlockDim - 1) / kBlockDim, (dims.y() + kBlockDim - 1) / kBlockDim,
            (dims.z() + kBlockDim - 1) / kBlockDim};
}

std::size_t blockIndex(const openvdb::Coord& blocks, int i, int j, int k, int channels, int c) {
    const std::size_t block = (std::size_t(k / kBlockDim) * blocks.y() + j / kBlockDim) * blocks.x() + i / kBlockDim;
    return block * channels + c;
}

/// Where a voxel sits in the coding order, and the voxels it is interpolated from.
/// Voxels code level by level, as in SZ3's interpolation: first anchors every
/// kAnchorStride voxels, then, for strides h = 8, 4, 2, 1, the voxels half-way
/// between decoded ones along x, then y, then z. A voxel of stride h along an axis
/// lies between decoded voxels at +-h (and +-3h) along it, so a decoder meets each
/// neighbour it reads before the voxel itself. Interpolating between neighbours
/// averages their quantisation errors, where Lorenzo's rule would sum seven.
struct Stencil {
    int axis = -1;  ///< 0, 1, 2 for x, y, z; -1 for an anchor
    int stride = 0;
};
constexpr int kAnchorStride = 16;

/// The coordinates of (i, j, k) one stride along @a axis (k counted from the slab's first slice).
struct Along {
    int i, j, k, axis;
    bool step(int by, const Slab& slab, std::size_t& at) const {
        int c[3] = {i, j, k};
        c[axis] += by;
        const int limit[3] = {slab.nx, slab.ny, slab.end};
        const int first = axis == 2 ? slab.begin : 0;
        if (c[axis] < first || c[axis] >= limit[axis]) return false;
        at = slab.local(c[0], c[1], c[2]);
        return true;
    }
};

/// Visits the voxels of @a slab in the coding order, with their stencils.
template <typename Visit>
void forEachInCodingOrder(const Slab& slab, Visit visit) {
    const int depth = slab.end - slab.begin;
    for (int k = 0; k < depth; k += kAnchorStride)
        for (int j = 0; j < slab.ny; j += kAnchorStride)
            for (int i = 0; i < slab.nx; i += kAnchorStride) visit(i, j, slab.begin + k, Stencil{});
    for (int h = kAnchorStride / 2; h >= 1; h /= 2) {
        for (int axis = 0; axis < 3; ++axis) {
            // Before this axis every h, along it the odd multiples of h, after it every 2h.
            const auto first = [&](int a) { return a == axis ? h : 0; };
            const auto by = [&](int a) { return a < axis ? h : 2 * h; };
            for (int k = first(2); k < depth; k += by(2))
                for (int j = first(1); j < slab.ny; j += by(1))
                    for (int i = first(0); i < slab.nx; i += by(0)) visit(i, j, slab.begin + k, Stencil{axis, h});
        }
    }
}

/// The interpolation of @a at's values at (i, j, k) from its stencil's neighbours:
/// cubic where four are there and @a cubic, else linear, else the one before.
template <typename ValueAt>
double interpolate(const Slab& slab, int i, int j, int k, const Stencil& stencil, bool cubic, ValueAt at) {
    const Along along{i, j, k, stencil.axis};
    std::size_t before = 0, after = 0, before3 = 0, after3 = 0;
    along.step(-stencil.stride, slab, before);  // always there: the voxel is an odd multiple of the stride
    if (!along.step(stencil.stride, slab, after)) return at(before);
    if (cubic && along.step(-3 * stencil.stride, slab, before3) && along.step(3 * stencil.stride, slab, after3)) {
        return (9.0 * (at(before) + at(after)) - at(before3) - at(after3)) / 16.0;
    }
    return 0.5 * (at(before) + at(after));
}

/// An anchor's prediction: the anchor before it along x, else y, else z, else zero.
template <typename ValueAt>
double previousAnchor(const Slab& slab, int i, int j, int k, ValueAt at) {
    if (i > 0) return at(slab.local(i - kAnchorStride, j, k));
    if (j > 0) return at(slab.local(i, j - kAnchorStride, k));
    if (k > slab.begin) return at(slab.local(i, j, k - kAnchorStride));
    return 0.0;
}

/// A source value in @a domain: its stored sample, or itself.
double toDomainValue(const ResidualDomain& domain, float value) {
    return domain.integers ? std::round((double(value) - domain.intercept) / domain.slope) : double(value);
}

/// The numbers the encoder and the decoder both compute with.
class DomainArithmetic {
public:
    explicit DomainArithmetic(const ResidualLayer& layer)
        : mDomain(layer.domain),
          mBound(layer.bound),
          mStep(layer.step()),
          mHalf(std::floor(mStep / 2.0)),
          mLow(layer.low),
          mHigh(layer.high) {}

    double toDomain(float value) const { return toDomainValue(mDomain, value); }
    float toValue(double domainValue) const {
        return float(mDomain.integers ? mDomain.intercept + mDomain.slope * domainValue : domainValue);
    }
    /// The prediction as the quantiser takes it: a whole sample in an integer domain.
    /// @return false where none is usable: non-finite, or in an integer domain past
    /// exact integers. Float values of any size are usable, since code() checks the
    /// bound on each value as a float holds it (data near 1e38 was stored exactly).
    bool usable(double& prediction) const {
        if (!std::isfinite(prediction)) return false;
        if (!mDomain.integers) return true;
        if (!(std::abs(prediction) <= kMaxPrediction)) return false;
        prediction = std::round(prediction);
        return true;
    }
    /// The code of @a target against @a prediction, or kResidualExact when its
    /// reconstruction would be past the bound from @a value (after rounding to float).
    std::int32_t code(double target, double prediction, float value) const {
        const double q = mDomain.integers ? std::floor((target - prediction + mHalf) / mStep)
                                          : std::round((double(value) - prediction) / mStep);
        if (!(std::abs(q) <= kMaxResidualCode)) return kResidualExact;
        const double reconstructed = std::clamp(prediction + q * mStep, mLow, mHigh);
        if (!(std::abs(double(toValue(reconstructed)) - double(value)) <= mBound)) return kResidualExact;
        return std::int32_t(q);
    }
    /// The decoded domain value of @a code over @a prediction, as the predictors read it.
    double decoded(double prediction, std::int32_t code) const {
        const double reconstructed = std::clamp(prediction + double(code) * mStep, mLow, mHigh);
        return mDomain.integers ? reconstructed : double(toValue(reconstructed));
    }

private:
    ResidualDomain mDomain;
    double mBound, mStep, mHalf, mLow, mHigh;
};

/// The bits a residual of @a r costs, about: the width of its quantised magnitude.
int costBits(double r, double step) {
    const double q = std::min(std::abs(r) / step + 0.5, 1e18);
    const auto n = std::uint64_t(q);
    return n == 0 ? 0 : 2 + int(64 - __builtin_clzll(n));
}

/// One channel of one slab, in the domain: the Gaussians' prediction G, and the
/// values D interpolated from (the source's for choosing, the decoded ones for coding).
struct SlabChannel {
    std::vector<double> gaussian, values;
};

/// The prediction of (i, j, k) by @a predictor, from part's G and D. The residual
/// from the Gaussians is mostly noise, which linear weights pass less of than cubic
/// ones (a gain of 0.5 against 0.64); the values themselves are smooth, where cubic wins.
double predict(ResidualPredictor predictor, const Slab& slab, const SlabChannel& part, int i, int j, int k,
               const Stencil& stencil) {
    const std::size_t at = slab.local(i, j, k);
    const auto value = [&](std::size_t n) { return part.values[n]; };
    const auto residual = [&](std::size_t n) { return part.values[n] - part.gaussian[n]; };
    const bool anchor = stencil.axis < 0;
    switch (predictor) {
        case ResidualPredictor::Gaussians:
            return part.gaussian[at];
        case ResidualPredictor::Neighbours:
            return anchor ? previousAnchor(slab, i, j, k, value) : interpolate(slab, i, j, k, stencil, true, value);
        case ResidualPredictor::Both:
            return part.gaussian[at] + (anchor ? previousAnchor(slab, i, j, k, residual)
                                               : interpolate(slab, i, j, k, stencil, false, residual));
    }
    return 0.0;
}

}  // namespace

double ResidualLayer::step() const {
    return domain.integers ? 2.0 * std::floor(bound / std::abs(domain.slope)) + 1.0 : 2.0 * bound;
}

ResidualDomain residualDomainOf(const FloatVolume& source, double slope, double intercept) {
    ResidualDomain domain{true, slope, intercept};
    if (!(slope != 0.0) || !std::isfinite(slope) || !std::isfinite(intercept)) return {false, 1.0, 0.0};
    for (const float value : source.values) {
        const double k = std::round((double(value) - intercept) / slope);
        if (!(std::abs(k) <= kMaxSampleMagnitude) || float(intercept + slope * k) != value) return {false, 1.0, 0.0};
    }
    return domain;
}

namespace {

void checkBound(double bound, const ResidualDomain& domain) {
    if (std::isnan(bound) || bound < 0.0 || std::isinf(bound)) {
        throw InputError("`max_error`",
                         "must be a finite number of the source's units, at least 0; got " + std::to_string(bound));
    }
    if (bound == 0.0 && !domain.integers) {
        throw InputError("`max_error`",
                         "0 asks for a lossless copy, which float data has no path to "
                         "(its values are not whole stored samples); give a bound above 0");
    }
}

void checkSameShape(const FloatVolume& a, const FloatVolume& b) {
    if (a.dims != b.dims || a.channels != b.channels || a.values.size() != b.values.size()) {
        throw std::invalid_argument("a residual layer needs the source and its prediction on one lattice");
    }
}

/// The source's range in the domain, which every reconstruction is clamped into:
/// a quantised step past it would only stray further from the source.
void setSourceRange(ResidualLayer& layer, const FloatVolume& source) {
    if (source.values.empty()) return;
    const auto [lo, hi] = std::minmax_element(source.values.begin(), source.values.end());
    const double a = toDomainValue(layer.domain, *lo), b = toDomainValue(layer.domain, *hi);
    layer.low = std::min(a, b);  // a negative slope turns the range over
    layer.high = std::max(a, b);
}

/// Converts the prediction's values into @a part's G, in the domain (unrounded).
void fillGaussian(SlabChannel& part, const FloatVolume& prediction, const Slab& slab, int c,
                  const ResidualDomain& domain) {
    const std::size_t first = std::size_t(slab.begin) * slab.nx * slab.ny;
    part.gaussian.resize(slab.voxels());
    part.values.assign(slab.voxels(), 0.0);
    for (std::size_t v = 0; v < slab.voxels(); ++v) {
        const double g = prediction.values[(first + v) * prediction.channels + c];
        part.gaussian[v] = domain.integers ? (g - domain.intercept) / domain.slope : g;
    }
}

/// Each block's predictor for channel @a c of @a slab: the one whose residuals
/// from the source's own neighbours cost the fewest bits.
void choosePredictors(ResidualLayer& layer, const FloatVolume& source, const Slab& slab, int c, SlabChannel& part,
                      const DomainArithmetic& math) {
    const std::size_t first = std::size_t(slab.begin) * slab.nx * slab.ny;
    for (std::size_t v = 0; v < slab.voxels(); ++v) {
        part.values[v] = math.toDomain(source.values[(first + v) * source.channels + c]);
    }
    const openvdb::Coord blocks = blocksOf(layer.dims);
    std::vector<std::array<std::uint64_t, kResidualPredictors>> cost(
        std::size_t(blocks.x()) * blocks.y() * ((slab.end - slab.begin + kBlockDim - 1) / kBlockDim), {0, 0, 0});
    const double step = layer.step();
    forEachInCodingOrder(slab, [&](int i, int j, int k, const Stencil& stencil) {
        const double target = part.values[slab.local(i, j, k)];
        const std::size_t block =
            (std::size_t((k - slab.begin) / kBlockDim) * blocks.y() + j / kBlockDim) * blocks.x() + i / kBlockDim;
        for (int p = 0; p < kResidualPredictors; ++p) {
            const double prediction = predict(ResidualPredictor(p), slab, part, i, j, k, stencil);
            cost[block][p] += std::isfinite(prediction) ? costBits(target - prediction, step) : 64;
        }
    });
    const std::size_t firstBlock = std::size_t(slab.begin / kBlockDim) * blocks.x() * blocks.y();
    for (std::size_t b = 0; b < cost.size(); ++b) {
        const auto best = std::min_element(cost[b].begin(), cost[b].end()) - cost[b].begin();
        layer.predictors[(firstBlock + b) * layer.channels + c] = ResidualPredictor(best);
    }
}

/// Codes channel @a c of @a slab with the chosen predictors; part.values becomes the decoded values.
void codeSlab(ResidualLayer& layer, const FloatVolume& source, const Slab& slab, int c, SlabChannel& part,
              const DomainArithmetic& math, std::vector<double>& exact) {
    const openvdb::Coord blocks = blocksOf(layer.dims);
    forEachInCodingOrder(slab, [&](int i, int j, int k, const Stencil& stencil) {
        const std::size_t voxel = source.indexOf(i, j, k);
        const float value = source.values[voxel * source.channels + c];
        const double target = math.toDomain(value);
        const auto predictor = layer.predictors[blockIndex(blocks, i, j, k, layer.channels, c)];
        double prediction = predict(predictor, slab, part, i, j, k, stencil);
        std::int32_t& code = layer.codes[voxel * layer.channels + c];
        code = math.usable(prediction) ? math.code(target, prediction, value) : kResidualExact;
        if (code == kResidualExact) exact.push_back(target);
        part.values[slab.local(i, j, k)] = code == kResidualExact ? target : math.decoded(prediction, code);
    });
}

/// codeSlab's inverse: channel @a c of @a slab into @a out, taking exact values from @a next on.
void decodeSlab(const ResidualLayer& layer, const Slab& slab, int c, SlabChannel& part, const DomainArithmetic& math,
                std::size_t& next, FloatVolume& out) {
    const openvdb::Coord blocks = blocksOf(layer.dims);
    forEachInCodingOrder(slab, [&](int i, int j, int k, const Stencil& stencil) {
        const std::size_t at = out.indexOf(i, j, k) * layer.channels + c;
        const std::int32_t code = layer.codes[at];
        double decoded;
        if (code == kResidualExact) {
            decoded = layer.exact[next++];
        } else {
            const auto predictor = layer.predictors[blockIndex(blocks, i, j, k, layer.channels, c)];
            double prediction = predict(predictor, slab, part, i, j, k, stencil);
            if (!math.usable(prediction)) throw std::runtime_error("a coded voxel has no prediction");
            decoded = math.decoded(prediction, code);
        }
        part.values[slab.local(i, j, k)] = decoded;
        out.values[at] = math.toValue(decoded);
    });
}

}  // namespace

ResidualLayer encodeResidualLayer(const FloatVolume& source, const FloatVolume& prediction, double bound,
                                  const ResidualDomain& domain) {
    checkSameShape(source, prediction);
    checkBound(bound, domain);
    ResidualLayer layer;
    layer.bound = bound;
    layer.domain = domain;
    layer.dims = source.dims;
    layer.channels = source.channels;
    const openvdb::Coord blocks = blocksOf(source.dims);
    layer.predictors.assign(std::size_t(blocks.x()) * blocks.y() * blocks.z() * source.channels,
                            ResidualPredictor::Gaussians);
    layer.codes.assign(source.values.size(), 0);
    setSourceRange(layer, source);
    const DomainArithmetic math(layer);
    const int slabs = residualSlabCount(source.dims);
    std::vector<std::vector<double>> exact(std::size_t(slabs) * source.channels);
    tbb::parallel_for(0, slabs, [&](int s) {
        const Slab slab = slabOf(source.dims, s);
        for (int c = 0; c < source.channels; ++c) {
            SlabChannel part;
            fillGaussian(part, prediction, slab, c, domain);
            choosePredictors(layer, source, slab, c, part, math);
            codeSlab(layer, source, slab, c, part, math, exact[std::size_t(s) * source.channels + c]);
        }
    });
    for (const auto& values : exact) layer.exact.insert(layer.exact.end(), values.begin(), values.end());
    return layer;
}

FloatVolume decodeResidualLayer(const ResidualLayer& layer, const FloatVolume& prediction) {
    if (prediction.dims != layer.dims || prediction.channels != layer.channels ||
        layer.codes.size() != prediction.values.size()) {
        throw std::runtime_error("the residual layer is not of the asset's source lattice");
    }
    if (!(layer.low <= layer.high)) throw std::runtime_error("the layer's source range is empty");
    const DomainArithmetic math(layer);
    const int slabs = residualSlabCount(layer.dims);
    // Where each slab's exact values begin: they are stored slab by slab.
    std::vector<std::size_t> firstExact(std::size_t(slabs) + 1, 0);
    const std::size_t slice = std::size_t(layer.dims.x()) * layer.dims.y() * layer.channels;
    for (int s = 0; s < slabs; ++s) {
        const Slab slab = slabOf(layer.dims, s);
        const auto begin = layer.codes.begin() + std::ptrdiff_t(slice * slab.begin);
        firstExact[s + 1] =
            firstExact[s] +
            std::size_t(std::count(begin, begin + std::ptrdiff_t(slice * (slab.end - slab.begin)), kResidualExact));
    }
    if (firstExact.back() != layer.exact.size())
        throw std::runtime_error("the layer's exact values do not match its codes");
    FloatVolume out(layer.dims, layer.channels);
    out.worldFromIndex = prediction.worldFromIndex;
    tbb::parallel_for(0, slabs, [&](int s) {
        const Slab slab = slabOf(layer.dims, s);
        std::size_t next = firstExact[s];
        for (int c = 0; c < layer.channels; ++c) {
            SlabChannel part;
            fillGaussian(part, prediction, slab, c, layer.domain);
            decodeSlab(layer, slab, c, part, math, next, out);
        }
    });
    return out;
}

}  // namespace gvr
