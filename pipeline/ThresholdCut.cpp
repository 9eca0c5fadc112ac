#include "pipeline/ThresholdCut.h"

#include "pipeline/Luminance.h"

namespace gvr {

ThresholdCut::ThresholdCut(const ValueMapping& mapping, int channels, std::optional<double> threshold,
                           std::optional<double> above)
    : mChannels(channels) {
    // physical = offset + scale * normalised per channel, and luminance is linear,
    // so each cut is one comparison in normalised units.
    const double offset = channels == 1 ? mapping.offset[0] : luminance(mapping.offset);
    if (threshold) mLimit = (*threshold - offset) / mapping.scale;
    if (above) mUpperLimit = (*above - offset) / mapping.scale;
}

bool ThresholdCut::cuts(const float* normalised) const {
    if (!mLimit && !mUpperLimit) return false;
    const double key = mChannels == 1 ? double(normalised[0]) : luminance(normalised);
    return (mLimit && key <= *mLimit) || (mUpperLimit && key >= *mUpperLimit);
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

std::optional<double> defaultExportThresholdAbove(const VolumeMetadata& source) {
    if (!source.thresholdAbove) return std::nullopt;
    if (source.background <= *source.thresholdAbove) return source.thresholdAbove;
    return 0.5 * (source.background + *source.thresholdAbove);
}

ThresholdCut defaultExportCut(const GaussianAsset& asset) {
    return ThresholdCut(asset.mapping, asset.source.channels, defaultExportThreshold(asset.source),
                        defaultExportThresholdAbove(asset.source));
}

}  // namespace gvr
