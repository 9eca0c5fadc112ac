/// @file ComparisonInput.h
/// @brief What `gvr eval` compares: a volume (a .vdb, a Gaussian asset as exported
/// onto its source grid, or anything ingest reads) or a single 2D image, as dense
/// float samples.
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
};

/// @throw InputError naming @a path when it cannot be read.
ComparisonInput loadComparisonInput(const std::string& path, const IngestOptions& options);

/// A grid in memory (float, double or Vec3s), over the voxels it stands for;
/// @a name names it in errors.
/// @throw InputError for any other value type, or when the voxels do not fit in memory.
ComparisonInput comparisonInputOf(openvdb::GridBase::ConstPtr grid, const std::string& name);

}  // namespace gvr
