/// @file ThresholdCut.h
/// @brief The rule a reconstruction obeys before anyone sees it: voxels whose
/// physical value (luminance for RGB) is at or below the threshold are background.
///
/// Export applies it to every voxel it writes, so the fit's own measurement and
/// `gvr eval` apply it too: every command that reports an asset's quality then
/// reports the voxels a user gets.
#pragma once

#include "pipeline/GaussianAsset.h"
#include "pipeline/ValueMapping.h"

#include <optional>

namespace gvr {

class ThresholdCut {
public:
    ThresholdCut() = default;  ///< cuts nothing
    /// @a threshold in physical units; std::nullopt cuts nothing. @a above, when
    /// set, cuts values at or above it too (a bright background).
    ThresholdCut(const ValueMapping& mapping, int channels, std::optional<double> threshold,
                 std::optional<double> above = std::nullopt);

    /// True when a voxel whose field value (normalised units, @a channels of
    /// them) is @a normalised becomes background.
    bool cuts(const float* normalised) const;

    /// Replaces a cut value by the background, normalised 0.
    void apply(float* normalised) const;

private:
    int mChannels = 1;
    std::optional<double> mLimit;  ///< in normalised units (of the luminance for RGB)
    std::optional<double> mUpperLimit;
};

/// What export uses when no threshold is given. The source holds no value between
/// its background and its ingest threshold, so a reconstructed value in that gap
/// goes to the nearer of the two: values below the midpoint become background.
/// (Cutting at the threshold itself loses accuracy on a chest CT whose background
/// is 1300 HU below it.) Without an ingest threshold: the source's minimum.
double defaultExportThreshold(const VolumeMetadata& source);

/// The same for a threshold from above: midway between it and a background above
/// it; unset when the source had none.
std::optional<double> defaultExportThresholdAbove(const VolumeMetadata& source);

/// The cut export makes by default for @a asset.
ThresholdCut defaultExportCut(const GaussianAsset& asset);

}  // namespace gvr
