#include "Adam.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace gvr {

Adam::Adam(std::size_t count, int channels, const AdamSettings& settings)
    : mSettings(settings), mFirst(count, channels), mSecond(count, channels) {}

void Adam::step(GaussianParameters& params, const GaussianParameters& gradient,
                const std::array<double, kGroupCount>& rates) {
    ++mSteps;
    const double correction1 = 1.0 - std::pow(mSettings.beta1, double(mSteps));
    const double correction2 = 1.0 - std::pow(mSettings.beta2, double(mSteps));
    for (int g = 0; g < kGroupCount; ++g) {
        std::vector<float>& values = params.values[g];
        const std::vector<float>& grad = gradient.values[g];
        std::vector<float>& m = mFirst.values[g];
        std::vector<float>& v = mSecond.values[g];
        const double rate = rates[g];
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, values.size(), 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t k = range.begin(); k != range.end(); ++k) {
                m[k] = float(mSettings.beta1 * m[k] + (1.0 - mSettings.beta1) * grad[k]);
                v[k] = float(mSettings.beta2 * v[k] + (1.0 - mSettings.beta2) * double(grad[k]) * grad[k]);
                const double mHat = m[k] / correction1;
                const double vHat = v[k] / correction2;
                values[k] -= float(rate * mHat / (std::sqrt(vHat) + mSettings.epsilon));
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
