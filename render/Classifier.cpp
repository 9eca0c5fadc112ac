#include "render/Classifier.h"

#include "pipeline/Luminance.h"

#include <algorithm>

namespace gvr {

Classifier::Classifier(TransferFunction tf, int channels, double colourScale)
    : mTf(std::move(tf)), mChannels(channels), mColourScale(colourScale) {}

std::array<float, 4> Classifier::operator()(const float* value) const {
    if (mChannels == 1) return mTf(value[0]);
    std::array<float, 4> rgba;
    for (int c = 0; c < 3; ++c) rgba[c] = float(std::clamp(value[c] * mColourScale, 0.0, 1.0));
    rgba[3] = mTf(luminance(value))[3];
    return rgba;
}

}  // namespace gvr
