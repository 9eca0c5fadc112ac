#include "pipeline/BlockLoss.h"

#include "pipeline/BlockKernel.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>

namespace gvr {

namespace {

/// The centre of a block's voxels, from its origin; moments are taken about it,
/// where they are small.
constexpr float kCentre = 0.5f * (kBlockDim - 1);

/// One Gaussian's kernel values along one row of a block, kept for pass 2.
struct RowTerms {
    float e[kBlockDim];
    std::uint32_t row;  ///< x * kBlockDim + y
};

/// A Gaussian's share of a block: its rows in terms[first, end).
struct Pair {
    std::uint32_t gaussian, first, end;
    double centreOffset[3];  ///< the block's centre - mean
};

/// BlockQuadratic for r a voxel's offset from the block's origin: G is the inverse
/// covariance and gLin = G d, for d = origin - mean.
__attribute__((always_inline)) inline BlockQuadratic quadraticOver(const ActiveGaussian& g, const double d[3]) {
    const float* inverse = g.inverseCovariance;
    const double G[3][3] = {{inverse[0], inverse[3], inverse[4]},
                            {inverse[3], inverse[1], inverse[5]},
                            {inverse[4], inverse[5], inverse[2]}};
    BlockQuadratic quad{};
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            quad.G[a][b] = G[a][b];
            quad.gLin[a] += G[a][b] * d[b];
        }
        quad.h += quad.gLin[a] * d[a];
    }
    return quad;
}

/// A block being evaluated; values channel-major, [channel][blockOffset].
struct BlockWork {
    float field[3][kBlockVoxels];
    float upstream[3][kBlockVoxels];
    float target[3 * kBlockVoxels];  ///< as VolumeTarget::blockValues gives them
    std::int32_t trainable[kBlockVoxels];
    std::vector<RowTerms> terms;
    std::vector<Pair> pairs;
};

/// What the whole pass shares.
struct PassInputs {
    const GaussianField& field;
    const BlockBins& bins;
    const VolumeTarget& target;
    const BlockLossSettings& settings;
};

/// The first and last of 0..kBlockDim-1 whose voxel o + k lies within [lower, upper].
bool offsetsWithin(float lower, float upper, int o, int range[2]) {
    range[0] = std::max(0, int(std::ceil(lower - float(o))));
    range[1] = std::min(kBlockDim - 1, int(std::floor(upper - float(o))));
    return range[0] <= range[1];
}

/// Pass 1 for one pair: amplitude x exp(-q/2) into the block's field over the sampled
/// rows of [xs] x [ys] (z in lanes of Floats: Floats4, or Floats8 in code compiled for
/// AVX2 and FMA), keeping the rows' kernel values.
template <typename Floats>
__attribute__((always_inline)) inline void addPairTerms(const BlockQuadratic& quad, const int xs[2], const int ys[2],
                                                        const SampledBlock& sampled, int rowStride, float cutoff2,
                                                        const float amplitude[3], int channels, BlockWork& work) {
    using Ints = decltype(Floats{} < Floats{});
    constexpr int kLanes = sizeof(Floats) / sizeof(float);
    const auto firstY = [&](int x) { return firstSampledY(x, ys[0], rowStride, sampled.rowPhase); };
    forEachRowCrossed(quad, xs[0], xs[1], firstY, ys[1], rowStride, cutoff2, [&](int x, int y, const RowParabola& row) {
        RowTerms terms;
        terms.row = std::uint32_t(x * kBlockDim + y);
        const int base = int(terms.row) * kBlockDim;
        int kept = 0;
        for (int part = 0; part < kBlockDim; part += kLanes) {
            const Floats q = rowQ<Floats>(row, part);
            const Ints keep = q <= cutoff2;
            for (int i = 0; i < kLanes; ++i) kept |= keep[i];
            const Floats e = kernelWhere(q, keep);
            std::memcpy(terms.e + part, &e, sizeof e);
            for (int c = 0; c < channels; ++c) {
                Floats f;
                std::memcpy(&f, work.field[c] + base + part, sizeof f);
                f += amplitude[c] * e;
                std::memcpy(work.field[c] + base + part, &f, sizeof f);
            }
        }
        if (kept) work.terms.push_back(terms);
    });
}

/// Moments of pass 2 in the block's frame, about its centre: s0 = sum t,
/// s1 = sum t r, s2 = sum t r r^T (upper triangle), upstreamE_c = sum upstream_c e.
struct BlockMoments {
    double s0 = 0.0, s1[3] = {0, 0, 0}, s2[3][3] = {}, upstreamE[3] = {0, 0, 0};
};

/// Pass 2 for one pair, with t = -e/2 sum_c upstream_c amplitude_c at each voxel.
template <typename Floats>
__attribute__((always_inline)) inline BlockMoments pairMoments(const Pair& pair, const float amplitude[3], int channels,
                                                               const BlockWork& work) {
    constexpr int kLanes = sizeof(Floats) / sizeof(float);
    constexpr int kParts = kBlockDim / kLanes;
    Floats v0[kParts] = {}, vx[kParts] = {}, vy[kParts] = {}, vxx[kParts] = {}, vyy[kParts] = {}, vxy[kParts] = {};
    Floats ve[3][kParts] = {};
    for (std::uint32_t k = pair.first; k < pair.end; ++k) {
        const RowTerms& terms = work.terms[k];
        const float xc = float(terms.row / kBlockDim) - kCentre, yc = float(terms.row % kBlockDim) - kCentre;
        const int base = int(terms.row) * kBlockDim;
        for (int p = 0; p < kParts; ++p) {
            Floats e, dot = {};
            std::memcpy(&e, terms.e + p * kLanes, sizeof e);
            for (int c = 0; c < channels; ++c) {
                Floats up;
                std::memcpy(&up, work.upstream[c] + base + p * kLanes, sizeof up);
                dot += amplitude[c] * up;
                ve[c][p] += up * e;
            }
            const Floats t = -0.5f * e * dot;
            v0[p] += t;
            vx[p] += xc * t;
            vy[p] += yc * t;
            vxx[p] += (xc * xc) * t;
            vyy[p] += (yc * yc) * t;
            vxy[p] += (xc * yc) * t;
        }
    }
    BlockMoments m;
    for (int p = 0; p < kParts; ++p) {
        for (int i = 0; i < kLanes; ++i) {
            const double z = double(p * kLanes + i) - kCentre;
            m.s0 += v0[p][i];
            m.s1[0] += vx[p][i];
            m.s1[1] += vy[p][i];
            m.s1[2] += z * v0[p][i];
            m.s2[0][0] += vxx[p][i];
            m.s2[1][1] += vyy[p][i];
            m.s2[2][2] += z * z * v0[p][i];
            m.s2[0][1] += vxy[p][i];
            m.s2[0][2] += z * vx[p][i];
            m.s2[1][2] += z * vy[p][i];
            for (int c = 0; c < channels; ++c) m.upstreamE[c] += ve[c][p][i];
        }
    }
    return m;
}

/// The moments about the Gaussian's mean: with d = centreOffset + r (r about the
/// block's centre), sum t d = s0 centreOffset + s1, and sum t d d^T expands the same way.
__attribute__((always_inline)) inline GradientSums aboutTheMean(const double centreOffset[3], BlockMoments m) {
    const double* o = centreOffset;
    const auto tdd = [&](int a, int b) {
        const double s2 = a <= b ? m.s2[a][b] : m.s2[b][a];
        return float(m.s0 * o[a] * o[b] + o[a] * m.s1[b] + m.s1[a] * o[b] + s2);
    };
    GradientSums sums;
    for (int a = 0; a < 3; ++a) {
        sums.upstreamE[a] = float(m.upstreamE[a]);
        sums.td[a] = float(m.s0 * o[a] + m.s1[a]);
    }
    sums.tdd[0] = tdd(0, 0);
    sums.tdd[1] = tdd(1, 1);
    sums.tdd[2] = tdd(2, 2);
    sums.tdd[3] = tdd(0, 1);
    sums.tdd[4] = tdd(0, 2);
    sums.tdd[5] = tdd(1, 2);
    return sums;
}

/// Residuals over the block's sampled rows into work.upstream (dL/df, zero where a
/// voxel is not trainable). @return sum of squared residuals.
double residuals(const PassInputs& pass, const SampledBlock& sampled, BlockWork& work, BlockOutcome& outcome) {
    const int channels = pass.field.channels();
    const int rowStride = pass.settings.rowStride;
    const float gain = float(2.0 * pass.settings.scale * sampled.weight);
    double squared = 0.0;
    for (int x = 0; x < kBlockDim; ++x) {
        for (int y = firstSampledY(x, 0, rowStride, sampled.rowPhase); y < kBlockDim; y += rowStride) {
            for (int z = 0; z < kBlockDim; ++z) {
                const int offset = (x * kBlockDim + y) * kBlockDim + z;
                if (!work.trainable[offset]) {
                    for (int c = 0; c < channels; ++c) work.upstream[c][offset] = 0.0f;
                    continue;
                }
                float voxelSquared = 0.0f, residual[3];
                for (int c = 0; c < channels; ++c) {
                    residual[c] = work.field[c][offset] - work.target[offset * channels + c];
                    voxelSquared += residual[c] * residual[c];
                    work.upstream[c][offset] = gain * residual[c];
                }
                squared += voxelSquared;
                ++outcome.voxels;
            }
        }
    }
    outcome.squared = squared;
    return squared;
}

/// One sampled block, forward and (with @a gradients) backward.
template <typename Floats>
__attribute__((always_inline)) inline double evaluateBlockWith(const PassInputs& pass, const SampledBlock& sampled,
                                                               BlockWork& work, BlockOutcome& outcome,
                                                               GradientChunks* gradients, std::size_t chunk) {
    const GaussianField& field = pass.field;
    const int channels = field.channels();
    const openvdb::Coord origin = pass.bins.grid().origin(sampled.block);
    pass.bins.grid().trainableMask(sampled.block, work.trainable);
    for (int c = 0; c < channels; ++c) std::fill_n(work.field[c], kBlockVoxels, 0.0f);
    work.terms.clear();
    work.pairs.clear();
    for (std::uint32_t index : pass.bins.gaussians(sampled.block)) {
        const ActiveGaussian& g = field.gaussians()[index];
        const Box& bounds = pass.bins.truncated(index);
        int xs[2], ys[2], zs[2];
        if (!offsetsWithin(bounds.lower[0], bounds.upper[0], origin.x(), xs) ||
            !offsetsWithin(bounds.lower[1], bounds.upper[1], origin.y(), ys) ||
            !offsetsWithin(bounds.lower[2], bounds.upper[2], origin.z(), zs)) {
            continue;
        }
        const double originOffset[3] = {origin.x() - double(g.mean[0]), origin.y() - double(g.mean[1]),
                                        origin.z() - double(g.mean[2])};
        const BlockQuadratic quad = quadraticOver(g, originOffset);
        // A copy: stores to the block could otherwise alias the Gaussian's amplitudes.
        float amplitude[3];
        std::copy(g.amplitude, g.amplitude + channels, amplitude);
        const std::uint32_t first = std::uint32_t(work.terms.size());
        addPairTerms<Floats>(quad, xs, ys, sampled, pass.settings.rowStride, field.cutoff2(), amplitude, channels,
                             work);
        if (work.terms.size() == first) continue;
        work.pairs.push_back({index,
                              first,
                              std::uint32_t(work.terms.size()),
                              {originOffset[0] + kCentre, originOffset[1] + kCentre, originOffset[2] + kCentre}});
    }
    pass.target.blockValues(origin, work.target);
    const double squared = residuals(pass, sampled, work, outcome);
    if (!gradients) return squared;
    for (const Pair& pair : work.pairs) {
        const ActiveGaussian& g = field.gaussians()[pair.gaussian];
        float amplitude[3];
        std::copy(g.amplitude, g.amplitude + channels, amplitude);
        gradients->sumsOf(chunk, pair.gaussian) +=
            aboutTheMean(pair.centreOffset, pairMoments<Floats>(pair, amplitude, channels, work));
    }
    return squared;
}

__attribute__((target("avx2,fma"))) double evaluateBlockAvx2Fma(const PassInputs& pass, const SampledBlock& sampled,
                                                                BlockWork& work, BlockOutcome& outcome,
                                                                GradientChunks* gradients, std::size_t chunk) {
    return evaluateBlockWith<Floats8>(pass, sampled, work, outcome, gradients, chunk);
}

double evaluateBlockFourLanes(const PassInputs& pass, const SampledBlock& sampled, BlockWork& work,
                              BlockOutcome& outcome, GradientChunks* gradients, std::size_t chunk) {
    return evaluateBlockWith<Floats4>(pass, sampled, work, outcome, gradients, chunk);
}

}  // namespace

double blockSquaredError(const GaussianField& field, const BlockBins& bins, const VolumeTarget& target,
                         const std::vector<SampledBlock>& blocks, const BlockLossSettings& settings,
                         GradientChunks* gradients, std::vector<BlockOutcome>* outcomes) {
    const PassInputs pass{field, bins, target, settings};
    const bool eightLanes = settings.kernel == BlockKernel::Best && processorHasAvx2Fma();
    const auto evaluate = eightLanes ? evaluateBlockAvx2Fma : evaluateBlockFourLanes;
    const std::size_t n = blocks.size();
    std::vector<BlockOutcome> local;
    std::vector<BlockOutcome>& seen = outcomes ? *outcomes : local;
    seen.assign(n, BlockOutcome());
    std::array<double, GradientChunks::kChunks> partial{};
    tbb::parallel_for(std::size_t(0), GradientChunks::kChunks, [&](std::size_t c) {
        const auto work = std::make_unique<BlockWork>();
        for (std::size_t k = c * n / GradientChunks::kChunks; k < (c + 1) * n / GradientChunks::kChunks; ++k) {
            partial[c] += double(blocks[k].weight) * evaluate(pass, blocks[k], *work, seen[k], gradients, c);
        }
    });
    double total = 0.0;
    for (double p : partial) total += p;
    return settings.scale * total;
}

}  // namespace gvr
