/// @file DenseCopy.h
/// @brief A grid's voxels copied dense, once the memory for them is known to be there.
#pragma once

#include "pipeline/FloatVolume.h"

#include <openvdb/openvdb.h>

#include <string>

namespace gvr {

/// sampleGrid(@a grid, @a box), after checkVolumeFitsInMemory(): a box that comes
/// from a file's metadata (volumeBox) is input like a header, and may claim more
/// voxels than any memory holds.
/// @param file  names the input in the error
/// @param task  what the copy is for, as the message says it ("compare", "export")
FloatVolume denseCopy(const openvdb::GridBase& grid, const openvdb::CoordBBox& box, const std::string& file,
                      const std::string& task);

}  // namespace gvr
