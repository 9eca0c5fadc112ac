/// @file DenseVolume.h
/// @brief A decoded source volume, before it becomes a sparse grid.
#pragma once

#include "pipeline/SampleType.h"
#include "pipeline/VolumeMetadata.h"

#include <openvdb/Types.h>
#include <openvdb/math/Mat4.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gvr {

/// Samples stay in the source datatype (i fastest, then j, then k; channels
/// interleaved), so a 16-bit CT waits for conversion at half the size of float32.
struct DenseVolume {
    std::array<std::int64_t, 3> dims{0, 0, 0};
    int channels = 1;  ///< 1 for grey, 3 for RGB
    SampleType type = SampleType::UInt8;
    std::vector<unsigned char> samples;
    double slope = 1.0;  ///< physical value = slope * stored + intercept
    double intercept = 0.0;
    /// Index space (voxel centres at integers) to world millimetres, in OpenVDB's
    /// row-vector convention: world = index * worldFromIndex.
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
    std::string modality = "unknown";
    std::optional<NiftiCodes> niftiCodes;  ///< a NIfTI source's space codes and units
    /// The physical value that the format marks as no data (DICOM's Pixel Padding
    /// Value: the scanner's out-of-field voxels), when it marks one.
    std::optional<double> markedPadding;
    std::vector<std::string> warnings;  ///< things the user should know, one line each

    std::uint64_t voxelCount() const {
        return std::uint64_t(dims[0]) * std::uint64_t(dims[1]) * std::uint64_t(dims[2]);
    }
    std::uint64_t sampleBytes() const { return voxelCount() * channels * bytesPerSample(type); }

    template <typename T>
    const T* data() const {
        return reinterpret_cast<const T*>(samples.data());
    }
    template <typename T>
    T* data() {
        return reinterpret_cast<T*>(samples.data());
    }
};

/// Builds OpenVDB's matrix from the usual 3x4 affine, where
/// world = rows * (i, j, k, 1)^T, as NIfTI's srow and DICOM's geometry give it.
openvdb::math::Mat4d worldFromIndexRows(const double rows[3][4]);

/// Axis-aligned voxels of @a spacingMm, with index 0 at the world origin.
openvdb::math::Mat4d worldFromSpacing(const openvdb::Vec3d& spacingMm);

/// Checks @a volume's dimensions against the memory at hand, then sizes its sample
/// buffer. Call it after dims, channels and type are known from a header.
/// @throw InputError naming @a file when the header asks for an absurd size.
void allocateSamples(DenseVolume& volume, const std::string& file);

/// The same check, but the buffer is only reserved and left empty: a reader appends
/// what the file really holds, so a forged header costs address space, not memory.
void reserveSamples(DenseVolume& volume, const std::string& file);

}  // namespace gvr
