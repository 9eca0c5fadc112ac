#include "pipeline/Loss.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace gvr {

void GradientChunks::reset(std::size_t count) {
    tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t c) {
        if (mSlots[c].size() != count) {
            mSlots[c].assign(count, kUntouched);
        } else {
            for (std::uint32_t index : mTouched[c]) mSlots[c][index] = kUntouched;
        }
        mTouched[c].clear();
    });
}

GradientSums& GradientChunks::sumsOf(std::size_t c, std::uint32_t index) {
    std::uint32_t& slot = mSlots[c][index];
    if (slot != kUntouched) return sumsAt(c, slot);
    slot = std::uint32_t(mTouched[c].size());
    mTouched[c].push_back(index);
    if (slot / kPageSums == mPages[c].size()) mPages[c].push_back(std::make_unique<GradientSums[]>(kPageSums));
    GradientSums& fresh = sumsAt(c, slot);
    fresh = GradientSums();
    return fresh;
}

std::size_t GradientChunks::sumInto(const GaussianField& field, const GaussianParameters& params, std::size_t begin,
                                    std::size_t end, GaussianParameters& gradient) const {
    if (gradient.count() != end - begin || gradient.channels != field.channels()) {
        gradient = GaussianParameters(end - begin, field.channels());
    } else {
        for (std::vector<float>& values : gradient.values) std::fill(values.begin(), values.end(), 0.0f);
    }
    std::size_t touched = 0;
    for (std::size_t index = begin; index != end; ++index) {
        GradientSums total;
        bool written = false;
        for (std::size_t c = 0; c < kChunks; ++c) {  // chunk order, whatever the threads did
            const std::uint32_t slot = mSlots[c][index];
            if (slot == kUntouched) continue;
            total += sumsAt(c, slot);
            written = true;
        }
        if (!written) continue;
        accumulateGradient(params, field.gaussians()[index], index, total, gradient, index - begin);
        ++touched;
    }
    return touched;
}

namespace {

/// One Gaussian's share of the field at a point, kept for the backward pass.
struct Contribution {
    std::uint32_t index;
    float e;
    float d[3];  ///< x - mean
};

/// f(x) into value[] from the Gaussians @a ids[0..count), recording every
/// contribution inside the cutoff. @a idsAscending: the ids come sorted, as
/// BlockBins keeps them, so the contributions need no sorting.
void evaluateRecorded(const GaussianField& field, const float x[3], const std::uint32_t* ids, std::size_t count,
                      bool idsAscending, float* value, std::vector<Contribution>& contributions) {
    contributions.clear();
    const int channels = field.channels();
    for (int c = 0; c < channels; ++c) value[c] = 0.0f;
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t index = ids[k];
        const ActiveGaussian& g = field.gaussians()[index];
        float u[3];
        const float q = mahalanobis2(g, x, u);
        if (q > field.cutoff2()) continue;
        contributions.push_back({index, std::exp(-0.5f * q), {x[0] - g.mean[0], x[1] - g.mean[1], x[2] - g.mean[2]}});
    }
    // Sum in index order, so the result does not depend on the BVH traversal.
    if (!idsAscending) {
        std::sort(contributions.begin(), contributions.end(),
                  [](const Contribution& a, const Contribution& b) { return a.index < b.index; });
    }
    for (const Contribution& contribution : contributions) {
        const ActiveGaussian& g = field.gaussians()[contribution.index];
        for (int c = 0; c < channels; ++c) value[c] += g.amplitude[c] * contribution.e;
    }
}

/// The field at @a x into @a value, and each Gaussian's part into @a contributions:
/// from the bins if given, else from the BVH.
void evaluateAt(const GaussianField& field, const float x[3], const BlockBins* bins, std::vector<std::uint32_t>& hits,
                std::vector<Contribution>& contributions, float* value) {
    if (bins) {
        const std::vector<std::uint32_t>& near = bins->gaussiansNear(x);
        evaluateRecorded(field, x, near.data(), near.size(), true, value, contributions);
    } else {
        field.bvh().query(x, hits);
        evaluateRecorded(field, x, hits.data(), hits.size(), false, value, contributions);
    }
}

/// Sum of w_s |f(x_s) - t_s|^2 over points [begin, end), point by point.
double pointsSquaredError(const GaussianField& field, const SampleSet& samples, std::size_t begin, std::size_t end,
                          double scale, GradientChunks* gradients, std::size_t chunk, const BlockBins* bins) {
    const int channels = field.channels();
    std::vector<std::uint32_t> hits;
    std::vector<Contribution> contributions;
    float value[3], upstream[3];
    double sum = 0.0;
    for (std::size_t s = begin; s < end; ++s) {
        evaluateAt(field, samples.points[s].data(), bins, hits, contributions, value);
        float squared = 0.0f;
        for (int ch = 0; ch < channels; ++ch) {
            const float residual = value[ch] - samples.targets[s * channels + ch];
            squared += residual * residual;
            upstream[ch] = float(2.0 * scale * samples.weights[s] * residual);
        }
        sum += double(samples.weights[s]) * squared;
        if (!gradients) continue;
        for (const Contribution& c : contributions) {
            gradients->sumsOf(chunk, c.index).add(field.gaussians()[c.index], channels, c.d, c.e, upstream);
        }
    }
    return sum;
}

}  // namespace

std::vector<float> residualsAt(const GaussianField& field, const SampleSet& samples, const BlockBins* bins) {
    const int channels = field.channels();
    std::vector<float> out(samples.size() * channels);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size()),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<std::uint32_t> hits;
                          std::vector<Contribution> contributions;
                          float value[3];
                          for (std::size_t s = range.begin(); s < range.end(); ++s) {
                              evaluateAt(field, samples.points[s].data(), bins, hits, contributions, value);
                              for (int c = 0; c < channels; ++c)
                                  out[s * channels + c] = samples.targets[s * channels + c] - value[c];
                          }
                      });
    return out;
}

double weightedSquaredError(const GaussianField& field, const SampleSet& samples, double scale,
                            GradientChunks* gradients, const BlockBins* bins) {
    const std::size_t n = samples.size();
    std::array<double, GradientChunks::kChunks> partial{};
    tbb::parallel_for(std::size_t(0), GradientChunks::kChunks, [&](std::size_t c) {
        partial[c] = pointsSquaredError(field, samples, c * n / GradientChunks::kChunks,
                                        (c + 1) * n / GradientChunks::kChunks, scale, gradients, c, bins);
    });
    double total = 0.0;
    for (double p : partial) total += p;
    return scale * total;
}

}  // namespace gvr
