/// @file VolumeMetadata.h
/// @brief What gvr records about an ingested volume, kept as metadata on its grid.
///
/// Every grid that `gvr ingest` writes carries these fields (keys prefixed "gvr_"),
/// so later stages can map values back to physical units and report compression
/// ratios against the original file.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#include <string>

namespace gvr {

struct VolumeMetadata {
    std::string sourceFile;
    std::string modality = "unknown";  ///< "CT", "MR", ... or "unknown"
    std::string sourceType;            ///< sampleTypeName() of one stored channel
    int channels = 1;                  ///< 1 for grey, 3 for RGB
    openvdb::Vec3i dims{0, 0, 0};      ///< source voxels along i, j, k
    openvdb::Vec3d spacingMm{1, 1, 1}; ///< length of each index axis in world millimetres
    double valueMin = 0;               ///< physical units, over all finite source voxels
    double valueMax = 0;               ///< (for RGB: over the luminance)
    double background = 0;             ///< value that inactive voxels stand for, same units
    std::optional<double> threshold;   ///< voxels at or below it were deactivated

    /// voxels × channels × bytes per sample of the source datatype: the size that
    /// compression ratios are measured against.
    std::uint64_t rawSourceBytes() const;
};

/// Length of each index axis in world units (OpenVDB's row-vector matrix).
openvdb::Vec3d axisSpacing(const openvdb::math::Mat4d& worldFromIndex);

/// True when two index-to-world matrices agree to @a relativeTolerance of their
/// largest linear entry (at least 1 mm): the same voxels in the same place.
bool samePlacement(const openvdb::math::Mat4d& a, const openvdb::math::Mat4d& b, double relativeTolerance);

void writeVolumeMetadata(const VolumeMetadata& metadata, openvdb::GridBase& grid);

/// @return the metadata, or std::nullopt for a grid that gvr did not ingest.
std::optional<VolumeMetadata> readVolumeMetadata(const openvdb::GridBase& grid);

}  // namespace gvr
