/// @file VolumeClassifier.h
/// @brief The classifier that maps one render volume's values to colour and opacity.
#pragma once

#include "render/Classifier.h"
#include "render/RenderVolume.h"
#include "render/TransferPresets.h"

#include <string>

namespace gvr {

/// @a tf over @a volume's values (RGB colours scaled by its largest value).
Classifier volumeClassifier(const RenderVolume& volume, const TransferFunction& tf);

/// The preset @a preset (ct, ct-bone, mri, rgb, in any case) fitted to @a volume's
/// statistics; empty: the preset for data like these (defaultPreset). @a mismatch,
/// when given, receives presetMismatch()'s word on a preset that does not suit the data.
/// @throw InputError naming an unknown preset.
TransferFunction presetFor(const RenderVolume& volume, const std::string& preset, std::string* mismatch = nullptr);

}  // namespace gvr
