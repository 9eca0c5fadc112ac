#include "pipeline/Adam.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gvr {

namespace {
/// Its square stays well inside float range.
constexpr float kLargestGradient = 1e18f;
}  // namespace

Adam::Adam(std::size_t count, int channels, const AdamSettings& settings)
    : mSettings(settings), mFirst(count, channels), mSecond(count, channels) {}

void Adam::beginStep(const std::array<double, kGroupCount>& rates) {
    ++mSteps;
    mInverseCorrection2 = float(1.0 / (1.0 - std::pow(mSettings.beta2, double(mSteps))));
    for (int g = 0; g < kGroupCount; ++g) {
        mRate[g] = float(rates[g] / (1.0 - std::pow(mSettings.beta1, double(mSteps))));
    }
}

void Adam::update(GaussianParameters& params, const GaussianParameters& gradient, std::size_t begin, std::size_t end,
                  std::uint8_t* updated) {
    const float beta1 = float(mSettings.beta1), beta2 = float(mSettings.beta2);
    const float epsilon = float(mSettings.epsilon);
    std::fill(updated, updated + (end - begin), std::uint8_t(1));
    // Each group's new values go to scratch in one loop the compiler vectorises, and
    // are written back only for the Gaussians whose results are all finite.
    std::array<std::vector<float>, kGroupCount> values, first, second;
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t width = std::size_t(params.width(ParameterGroup(g)));
        const std::size_t from = begin * width, count = (end - begin) * width;
        const float* grad = gradient.values[g].data();
        const float* value = params.values[g].data() + from;
        const float* m = mFirst.values[g].data() + from;
        const float* v = mSecond.values[g].data() + from;
        values[g].resize(count);
        first[g].resize(count);
        second[g].resize(count);
        const float rate = mRate[g];
        for (std::size_t k = 0; k < count; ++k) {
            // A huge but finite gradient would make v infinite and freeze the parameter for good.
            const float clamped = std::clamp(grad[k], -kLargestGradient, kLargestGradient);
            first[g][k] = beta1 * m[k] + (1.0f - beta1) * clamped;
            second[g][k] = beta2 * v[k] + (1.0f - beta2) * clamped * clamped;
            values[g][k] = value[k] - rate * first[g][k] / (std::sqrt(second[g][k] * mInverseCorrection2) + epsilon);
        }
        for (std::size_t i = 0; i < end - begin; ++i) {
            for (std::size_t k = i * width; k < (i + 1) * width; ++k) {
                if (!std::isfinite(grad[k]) || !std::isfinite(values[g][k])) updated[i] = 0;
            }
        }
    }
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t width = std::size_t(params.width(ParameterGroup(g)));
        float* value = params.values[g].data() + begin * width;
        float* m = mFirst.values[g].data() + begin * width;
        float* v = mSecond.values[g].data() + begin * width;
        for (std::size_t i = 0; i < end - begin; ++i) {
            if (!updated[i]) continue;
            for (std::size_t k = i * width; k < (i + 1) * width; ++k) {
                value[k] = values[g][k];
                m[k] = first[g][k];
                v[k] = second[g][k];
            }
        }
    }
}

void Adam::keepOnly(const std::vector<bool>& keep) {
    mFirst.keepOnly(keep);
    mSecond.keepOnly(keep);
}

void Adam::permute(const std::vector<std::uint32_t>& order) {
    mFirst.permute(order);
    mSecond.permute(order);
}

void Adam::grow(std::size_t count) {
    for (GaussianParameters* moments : {&mFirst, &mSecond}) {
        for (int g = 0; g < kGroupCount; ++g) {
            moments->values[g].resize(count * std::size_t(moments->width(ParameterGroup(g))), 0.0f);
        }
    }
}

}  // namespace gvr
