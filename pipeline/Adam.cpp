#include "Adam.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {
/// Its square stays well inside float range.
constexpr float kLargestGradient = 1e18f;
}  // namespace

Adam::Adam(std::size_t count, int channels, const AdamSettings& settings)
    : mSettings(settings), mFirst(count, channels), mSecond(count, channels) {}

void Adam::step(GaussianParameters& params, const GaussianParameters& gradient,
                const std::array<double, kGroupCount>& rates) {
    ++mSteps;
    const float beta1 = float(mSettings.beta1), beta2 = float(mSettings.beta2);
    const float epsilon = float(mSettings.epsilon);
    const float inverseCorrection2 = float(1.0 / (1.0 - std::pow(mSettings.beta2, double(mSteps))));
    for (int g = 0; g < kGroupCount; ++g) {
        float* values = params.values[g].data();
        const float* grad = gradient.values[g].data();
        float* m = mFirst.values[g].data();
        float* v = mSecond.values[g].data();
        // The first moment's bias correction folds into the rate.
        const float rate = float(rates[g] / (1.0 - std::pow(mSettings.beta1, double(mSteps))));
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, params.values[g].size(), 16384),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                // A huge but finite gradient would make v infinite and freeze the parameter for good.
                const float g = std::clamp(grad[k], -kLargestGradient, kLargestGradient);
                m[k] = beta1 * m[k] + (1.0f - beta1) * g;
                v[k] = beta2 * v[k] + (1.0f - beta2) * g * g;
                values[k] -= rate * m[k] / (std::sqrt(v[k] * inverseCorrection2) + epsilon);
            }
        });
    }
}

void Adam::keepOnly(const std::vector<bool>& keep) {
    mFirst.keepOnly(keep);
    mSecond.keepOnly(keep);
}

void Adam::grow(std::size_t count) {
    for (GaussianParameters* moments : {&mFirst, &mSecond}) {
        for (int g = 0; g < kGroupCount; ++g) {
            moments->values[g].resize(count * std::size_t(moments->width(ParameterGroup(g))), 0.0f);
        }
    }
}

}  // namespace gvr
