/// @file NiftiWriter.h
/// @brief Dense volumes out as NIfTI-1, for medical tools.
#pragma once

#include "pipeline/FloatVolume.h"
#include "pipeline/SampleType.h"
#include "pipeline/VolumeMetadata.h"

#include <cstdint>
#include <string>

namespace gvr {

/// How a one-channel NIfTI stores its samples and names its space. RGB is
/// always RGB24.
struct NiftiStorage {
    SampleType type = SampleType::Float32;
    double slope = 1.0;  ///< physical = slope * stored + intercept (scl_slope, scl_inter)
    double intercept = 0.0;
    NiftiCodes codes{1, 1, 2};  ///< scanner-anatomical sform and qform, millimetres
    /// Why the samples are float32 although the source was not: empty otherwise.
    std::string float32Reason;
};

/// The source's datatype, scaling and codes (@a source as ingest recorded it),
/// or float32 with them when @a float32 asks for it or the source's type cannot
/// hold the values (a float64 source, a broken scaling).
NiftiStorage niftiStorageLike(const VolumeMetadata& source, bool float32);

/// Writes @a volume atomically as NIfTI-1 (compressed when @a path ends in .gz).
/// One channel goes into @a storage's type, rounded and clamped to its range;
/// three channels as RGB24 (rounded, clamped to 0..255). The sform and qform
/// carry worldFromIndex (RAS millimetres, as gvr's world is); a shear only the
/// sform can hold.
/// @return how many samples had to be clamped into the stored type's range.
/// @throw InputError naming @a path for another channel count or a failed write.
std::uint64_t writeNifti(const std::string& path, const FloatVolume& volume, const NiftiStorage& storage = {});

}  // namespace gvr
