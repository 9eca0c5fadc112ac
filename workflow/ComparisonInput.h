/// @file ComparisonInput.h
/// @brief What `gvr eval` compares: a volume (a .vdb, a Gaussian asset as exported
/// onto its source grid, or anything ingest reads, as it reads it: every voxel) or a
/// single 2D image, as dense float samples.
#pragma once

#include "io/Ingest.h"
#include "pipeline/FloatVolume.h"

#include <string>

namespace gvr {

struct ComparisonInput {
    FloatVolume volume;  ///< physical units; images in OpenImageIO's 0..1 scale
    /// The data range: the one gvr recorded at ingest, else max - min of the samples.
    double dataRange = 0.0;
    bool isImage = false;  ///< a single 2D image (PNG, EXR, ...), depth 1, every channel kept
    /// The grid the samples came from (null for an image): what labels are placed on.
    openvdb::GridBase::ConstPtr grid;
    /// What volume.foreground holds, in words.
    std::string foregroundRule = "the reference's active voxels";
    /// One flag per voxel (1 = left out of every measure), or empty: the voxels of a
    /// source read as it is that hold the value its format marks as no data.
    std::vector<std::uint8_t> excluded;
    std::size_t excludedVoxels = 0;
    std::string readAs;  ///< how the samples were read, in words
};

/// A source file (anything ingest reads but a .vdb) is read as it is, every voxel
/// active, so that what an ingest threshold drops counts: a fit of the chest scored
/// far higher against its thresholded grid than against the DICOM as decoded. Only
/// the voxels its format marks as no data (DICOM's Pixel Padding Value) are left out;
/// its foreground is what ingest would keep (above -950 HU for a CT, above the
/// minimum else), and its data range that of the voxels kept.
/// @throw InputError naming @a path when it cannot be read.
ComparisonInput loadComparisonInput(const std::string& path, const IngestOptions& options);

/// A grid in memory (float, double or Vec3s), over the voxels it stands for;
/// @a name names it in errors.
/// @throw InputError for any other value type, or when the voxels do not fit in memory.
ComparisonInput comparisonInputOf(openvdb::GridBase::ConstPtr grid, const std::string& name);

}  // namespace gvr
