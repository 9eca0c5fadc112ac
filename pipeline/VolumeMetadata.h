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

/// The space codes and units of a NIfTI source's header, so that a NIfTI export
/// gives them back (an MNI-aligned atlas stays aligned, a time unit survives).
struct NiftiCodes {
    int sform = 0;  ///< 0 unknown, 1 scanner, 2 aligned, 3 Talairach, 4 MNI
    int qform = 0;
    int xyztUnits = 0;  ///< NIfTI's packed space and time units
};

struct VolumeMetadata {
    std::string sourceFile;
    std::string modality = "unknown";   ///< "CT", "MR", ... or "unknown"
    std::string sourceType;             ///< sampleTypeName() of one stored channel
    int channels = 1;                   ///< 1 for grey, 3 for RGB
    openvdb::Vec3i dims{0, 0, 0};       ///< source voxels along i, j, k
    openvdb::Vec3d spacingMm{1, 1, 1};  ///< length of each index axis in world millimetres
    double valueMin = 0;                ///< physical units, over all finite source voxels
    double valueMax = 0;                ///< (for RGB: over the luminance)
    double background = 0;              ///< value that inactive voxels stand for, same units
    /// The lowest value, when ingest set it apart from the background: a CT's padding
    /// outside the reconstruction circle (inactive too, but not averaged into background).
    std::optional<double> padding;
    std::uint64_t paddingVoxels = 0;
    /// The value the source format marks as no data (DICOM's Pixel Padding Value),
    /// which comparisons with the source as read leave out.
    std::optional<double> markedPadding;
    std::optional<double> threshold;       ///< voxels at or below it were deactivated
    std::optional<double> thresholdAbove;  ///< and those at or above this (bright backgrounds)
    /// Voxels whose 32-bit integers the float grid rounded: beyond 2^24, 16777217
    /// becomes 16777216 (a label atlas or a count volume is then changed).
    std::uint64_t roundedVoxels = 0;
    /// How the source stored its samples: physical = storedSlope * stored + storedIntercept.
    double storedSlope = 1.0;
    double storedIntercept = 0.0;
    std::optional<NiftiCodes> niftiCodes;  ///< set when the source was NIfTI

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
