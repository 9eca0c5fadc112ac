/// @file ThresholdHoles.h
/// @brief How much of the inside of a subject a threshold removed: the check that
/// catches a CT threshold which deletes the lungs.
#pragma once

#include <openvdb/openvdb.h>

namespace gvr {

/// Of the voxels inside the outline of @a grid's active voxels, slice by slice
/// along z (active ones, and inactive ones that active ones enclose in their
/// slice), the share that is inactive. 0 for an empty grid.
double enclosedInactiveShare(const openvdb::GridBase& grid);

}  // namespace gvr
