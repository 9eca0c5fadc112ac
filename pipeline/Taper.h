/// @file Taper.h
/// @brief A weight that fades a brick's voxels out across its faces with its
/// neighbours, so that the weights of all bricks add up to one at every voxel.
///
/// Along an axis, a brick whose core starts at a cut c (a face shared with the
/// brick before it) has weight sin^2(pi/2 t), t = (x - c + width + 1/2) / (2 width),
/// clamped to [0, 1]; the brick before it has the mirror image, cos^2 of the same
/// angle, so the two add up to one. Faces on the volume's boundary do not fade. The
/// weight is the product over the axes, and the bricks' products add up to one
/// because the bricks form a lattice.
#pragma once

#include <openvdb/openvdb.h>

namespace gvr {

struct Taper {
    openvdb::CoordBBox core;    ///< the brick's own voxels
    openvdb::CoordBBox volume;  ///< the box that the bricks tile
    int width = 0;              ///< voxels on each side of a face over which the weight fades

    /// In [0, 1]; zero beyond @a width voxels outside the core.
    float at(const openvdb::Coord& ijk) const;
};

}  // namespace gvr
