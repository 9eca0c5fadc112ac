#include "Loss.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace gvr {

void GradientChunks::reset(std::size_t count, int channels) {
    tbb::parallel_for(std::size_t(0), kChunks, [&](std::size_t c) {
        GaussianParameters& buffer = mChunks[c];
        if (buffer.count() != count || buffer.channels != channels) {
            buffer = GaussianParameters(count, channels);
        } else {
            buffer.setZero();
        }
    });
}

void GradientChunks::sumInto(GaussianParameters& gradient) const {
    const GaussianParameters& first = mChunks[0];
    gradient = first;
    for (int g = 0; g < kGroupCount; ++g) {
        std::vector<float>& out = gradient.values[g];
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 8192),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t c = 1; c < kChunks; ++c) {
                const std::vector<float>& in = mChunks[c].values[g];
                for (std::size_t k = range.begin(); k != range.end(); ++k) out[k] += in[k];
            }
        });
    }
}

namespace {

/// One Gaussian's share of the field at a point, kept for the backward pass.
struct Contribution {
    std::uint32_t index;
    float e;
    float u[3];
};

/// f(x) into value[], recording every contribution inside the cutoff.
void evaluateRecorded(const GaussianField& field, const float x[3], float* value,
                      std::vector<std::uint32_t>& hits, std::vector<Contribution>& contributions) {
    field.bvh().query(x, hits);
    contributions.clear();
    const int channels = field.channels();
    for (int c = 0; c < channels; ++c) value[c] = 0.0f;
    for (std::uint32_t index : hits) {
        Contribution contribution{index, 0.0f, {}};
        const float q = mahalanobis2(field.gaussians()[index], x, contribution.u);
        if (q > field.cutoff2()) continue;
        contribution.e = std::exp(-0.5f * q);
        contributions.push_back(contribution);
    }
    // Sum in index order, so the result does not depend on the BVH traversal.
    std::sort(contributions.begin(), contributions.end(),
              [](const Contribution& a, const Contribution& b) { return a.index < b.index; });
    for (const Contribution& contribution : contributions) {
        const ActiveGaussian& g = field.gaussians()[contribution.index];
        for (int c = 0; c < channels; ++c) value[c] += g.amplitude[c] * contribution.e;
    }
}

}  // namespace

double weightedSquaredError(const GaussianField& field, const SampleSet& samples, double scale,
                            GradientChunks* gradients, std::vector<float>* squaredResiduals) {
    const int channels = field.channels();
    const std::size_t n = samples.size();
    if (squaredResiduals) squaredResiduals->assign(n, 0.0f);
    std::array<double, GradientChunks::kChunks> partial{};
    tbb::parallel_for(std::size_t(0), GradientChunks::kChunks, [&](std::size_t c) {
        std::vector<std::uint32_t> hits;
        std::vector<Contribution> contributions;
        float value[3], upstream[3];
        double sum = 0.0;
        for (std::size_t s = c * n / GradientChunks::kChunks; s < (c + 1) * n / GradientChunks::kChunks; ++s) {
            const float* x = samples.points[s].data();
            evaluateRecorded(field, x, value, hits, contributions);
            float squared = 0.0f;
            for (int ch = 0; ch < channels; ++ch) {
                const float residual = value[ch] - samples.targets[s * channels + ch];
                squared += residual * residual;
                upstream[ch] = float(2.0 * scale * samples.weights[s] * residual);
            }
            sum += double(samples.weights[s]) * squared;
            if (squaredResiduals) (*squaredResiduals)[s] = squared;
            if (!gradients) continue;
            GaussianParameters& buffer = gradients->chunk(c);
            for (const Contribution& c : contributions) {
                accumulateGradient(field.gaussians()[c.index], c.index, x, c.u, c.e, upstream, buffer);
            }
        }
        partial[c] = sum;
    });
    double total = 0.0;
    for (double p : partial) total += p;
    return scale * total;
}

}  // namespace gvr
