/// @file Classifier.h
/// @brief Samples in physical units to colour and opacity: one transfer function,
/// applied identically by every renderer.
#pragma once

#include "pipeline/TransferFunction.h"

#include <array>
#include <cmath>

namespace gvr {

/// Opacities are per reference length (one voxel: the volume's smallest voxel
/// edge); a path of r reference lengths has opacity 1 - (1 - alpha)^r.
class Classifier {
public:
    /// Grey data: colour and opacity from @a tf at the value. RGB data: colour from
    /// the sample times @a colourScale (clamped to [0, 1]), opacity from @a tf at the
    /// luminance.
    Classifier(TransferFunction tf, int channels, double colourScale = 1.0);

    /// Straight (not premultiplied) RGBA of one sample of channels() floats.
    std::array<float, 4> operator()(const float* value) const;
    /// The colour of an RGB sample, without its opacity.
    std::array<float, 3> colour(const float* value) const;

    int channels() const { return mChannels; }
    const TransferFunction& transferFunction() const { return mTf; }
    double colourScale() const { return mColourScale; }

private:
    TransferFunction mTf;
    int mChannels;
    double mColourScale;
};

/// Opacity of a path @a lengthRatio reference lengths long.
inline float opacityOverLength(float alpha, double lengthRatio) {
    if (alpha >= 1.0f) return 1.0f;
    if (lengthRatio == 1.0) return alpha;  // the common case, spared a pow per sample
    return float(1.0 - std::pow(1.0 - double(alpha), lengthRatio));
}

}  // namespace gvr
