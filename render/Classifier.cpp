#include "render/Classifier.h"

#include "pipeline/Luminance.h"

#include <algorithm>

namespace gvr {

Classifier::Classifier(TransferFunction tf, int channels, double colourScale)
    : mTf(std::move(tf)), mChannels(channels), mColourScale(colourScale) {}

std::array<float, 4> Classifier::operator()(const float* value) const {
    if (mChannels == 1) return mTf(value[0]);
    const std::array<float, 3> rgb = colour(value);
    return {rgb[0], rgb[1], rgb[2], mTf(luminance(value))[3]};
}

std::array<float, 3> Classifier::colour(const float* value) const {
    std::array<float, 3> rgb;
    for (int c = 0; c < 3; ++c) rgb[c] = float(std::clamp(value[c] * mColourScale, 0.0, 1.0));
    return rgb;
}

}  // namespace gvr
