#include "ThresholdCut.h"

#include "Luminance.h"

namespace gvr {

ThresholdCut::ThresholdCut(const ValueMapping& mapping, int channels, std::optional<double> threshold)
    : mChannels(channels) {
    if (!threshold) return;
    // physical = offset + scale * normalised per channel, and luminance is linear,
    // so the cut is one comparison in normalised units.
    const double offset = channels == 1 ? mapping.offset[0] : luminance(mapping.offset);
    mLimit = (*threshold - offset) / mapping.scale;
}

bool ThresholdCut::cuts(const float* normalised) const {
    if (!mLimit) return false;
    const double key = mChannels == 1 ? double(normalised[0]) : luminance(normalised);
    return key <= *mLimit;
}

void ThresholdCut::apply(float* normalised) const {
    if (!cuts(normalised)) return;
    for (int c = 0; c < mChannels; ++c) normalised[c] = 0.0f;
}

double defaultExportThreshold(const VolumeMetadata& source) {
    if (!source.threshold) return source.valueMin;
    if (source.background >= *source.threshold) return *source.threshold;
    return 0.5 * (source.background + *source.threshold);
}

ThresholdCut defaultExportCut(const GaussianAsset& asset) {
    return ThresholdCut(asset.mapping, asset.source.channels, defaultExportThreshold(asset.source));
}

}  // namespace gvr
