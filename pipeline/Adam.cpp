#include "Adam.h"

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {
/// Its square stays well inside float range.
constexpr float kLargestGradient = 1e18f;
/// The widest group: rotations, four floats (colours are at most three).
constexpr int kWidest = 4;
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

bool Adam::update(GaussianParameters& params, const GaussianParameters& gradient, std::size_t index) {
    const float beta1 = float(mSettings.beta1), beta2 = float(mSettings.beta2);
    const float epsilon = float(mSettings.epsilon);
    // Everything is computed first and written only if it is all finite.
    float values[kGroupCount][kWidest], first[kGroupCount][kWidest], second[kGroupCount][kWidest];
    bool finite = true;
    for (int g = 0; g < kGroupCount; ++g) {
        const ParameterGroup group = ParameterGroup(g);
        const float* grad = gradient.at(group, index);
        const float* value = params.at(group, index);
        const float* m = mFirst.at(group, index);
        const float* v = mSecond.at(group, index);
        for (int k = 0; k < params.width(group); ++k) {
            finite = finite && std::isfinite(grad[k]);
            // A huge but finite gradient would make v infinite and freeze the parameter for good.
            const float clamped = std::clamp(grad[k], -kLargestGradient, kLargestGradient);
            first[g][k] = beta1 * m[k] + (1.0f - beta1) * clamped;
            second[g][k] = beta2 * v[k] + (1.0f - beta2) * clamped * clamped;
            values[g][k] = value[k] - mRate[g] * first[g][k] / (std::sqrt(second[g][k] * mInverseCorrection2) + epsilon);
            finite = finite && std::isfinite(values[g][k]);
        }
    }
    if (!finite) return false;
    for (int g = 0; g < kGroupCount; ++g) {
        const ParameterGroup group = ParameterGroup(g);
        const int width = params.width(group);
        std::copy_n(values[g], width, params.at(group, index));
        std::copy_n(first[g], width, mFirst.at(group, index));
        std::copy_n(second[g], width, mSecond.at(group, index));
    }
    return true;
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
