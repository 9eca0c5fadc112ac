/// @file Trilinear.h
/// @brief Trilinear interpolation between voxel centres, whatever holds the voxels:
/// the target's grid, a dense volume, the renderer's grid.
#pragma once

#include <openvdb/openvdb.h>

#include <cmath>

namespace gvr {

/// Calls @a visit(corner, weight) for each of the eight voxels around index-space
/// point @a x whose weight is not zero, x fastest; the weights sum to 1. Callers
/// keep @a x within reach of int voxel indices.
template <typename Visit>
void forEachTrilinearCorner(const openvdb::Vec3d& x, const Visit& visit) {
    const openvdb::Coord base(int(std::floor(x[0])), int(std::floor(x[1])), int(std::floor(x[2])));
    const double t[3] = {x[0] - base.x(), x[1] - base.y(), x[2] - base.z()};
    for (int corner = 0; corner < 8; ++corner) {
        const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
        const double weight = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
        if (weight != 0.0) visit(base.offsetBy(di, dj, dk), weight);
    }
}

}  // namespace gvr
