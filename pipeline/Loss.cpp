#include "Loss.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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

double weightedSquaredError(const GaussianField& field, const SampleSet& samples, double scale,
                            GradientChunks* gradients, std::vector<float>* squaredResiduals) {
    const int channels = field.channels();
    const std::size_t n = samples.size();
    if (squaredResiduals) squaredResiduals->assign(n, 0.0f);
    std::array<double, GradientChunks::kChunks> partial{};
    tbb::parallel_for(std::size_t(0), GradientChunks::kChunks, [&](std::size_t c) {
        std::vector<std::uint32_t> hits;
        float value[3], upstream[3];
        double sum = 0.0;
        for (std::size_t s = c * n / GradientChunks::kChunks; s < (c + 1) * n / GradientChunks::kChunks; ++s) {
            const float* x = samples.points[s].data();
            field.evaluate(x, value, hits);
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
            for (std::uint32_t index : hits) {
                accumulateGradient(field.gaussians()[index], index, x, field.cutoff2(), upstream, buffer);
            }
        }
        partial[c] = sum;
    });
    double total = 0.0;
    for (double p : partial) total += p;
    return scale * total;
}

}  // namespace gvr
