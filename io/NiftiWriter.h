/// @file NiftiWriter.h
/// @brief Dense volumes out as NIfTI-1, for medical tools.
#pragma once

#include "FloatVolume.h"

#include <string>

namespace gvr {

/// Writes @a volume atomically as NIfTI-1 (compressed when @a path ends in .gz):
/// float32 for one channel, RGB24 (rounded, clamped to 0..255) for three. The
/// sform and qform carry worldFromIndex (RAS millimetres, as gvr's world is); a
/// shear only the sform can hold.
/// @throw InputError naming @a path for another channel count or a failed write.
void writeNifti(const std::string& path, const FloatVolume& volume);

}  // namespace gvr
