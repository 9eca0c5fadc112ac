/// @file TransferPresets.h
/// @brief The named transfer functions: ct, ct-bone, mri and rgb.
///
/// - ct: soft tissue in Hounsfield units; skin and muscle in warm tones from -300 HU,
///   bone white and denser from 300 HU.
/// - ct-bone: bone window in HU, transparent below 150 HU.
/// - mri: a window from the volume's own percentiles: transparent at the 30th,
///   white and most opaque at the 99.5th (for any grey data without HU).
/// Percentiles are taken over the content: values more than 2 % of the range away
/// from the background.
/// - rgb: colour from the data; opacity from the luminance, rising away from the
///   background's luminance (dark tissue on white paper and bright tissue on black
///   both work), between the 2nd and 98th percentiles of the content.
/// Opacities are per voxel of path.
#pragma once

#include "pipeline/TransferFunction.h"

#include <string>
#include <vector>

namespace gvr {

/// What the percentile-based presets look at.
struct VolumeStatistics {
    std::vector<float> values;  ///< a sample of the volume's content (luminance for RGB)
    double background = 0.0;    ///< what surrounds the subject: the median on the volume's faces
    bool hounsfield = false;    ///< CT in HU: the data reach below -500
};

/// @throw InputError naming the preset when @a name is unknown (the message lists the presets).
TransferFunction presetTransferFunction(const std::string& name, const VolumeStatistics& statistics);

/// The preset for data like this: rgb for colour, ct for HU, else mri.
std::string defaultPreset(int channels, const VolumeStatistics& statistics);

/// Whether preset @a name can classify data of @a channels: rgb colour, the others grey.
bool presetTakes(const std::string& name, int channels);

/// Why preset @a name does not suit these data, naming the one that does; empty
/// when it suits them. A Hounsfield preset (ct, ct-bone) on data that never reach
/// below -500 (air in HU) would turn everything into one opaque block.
std::string presetMismatch(const std::string& name, int channels, const VolumeStatistics& statistics);

}  // namespace gvr
