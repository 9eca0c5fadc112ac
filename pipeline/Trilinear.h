/// @file Trilinear.h
/// @brief Trilinear interpolation between voxel centres, whatever holds the voxels:
/// the target's grid, a dense volume, the renderer's grid and bricks.
///
/// Two forms, for two kinds of reader: forEachTrilinearCorner() hands out weighted
/// corners (x fastest, zero weights skipped), for sparse lookups and sums;
/// blendCorners() blends eight fetched corners (z fastest, as a leaf holds its
/// voxels) in three nested lerps, which the renderer's bricks also run axis by axis
/// to the bit.
#pragma once

#include <openvdb/openvdb.h>

#include <cmath>
#include <type_traits>

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

/// The voxel below @a x along one axis: std::floor's, in fewer instructions where the
/// processor has no rounding instruction (SSE4.1) for it. @a x lies well inside int's range.
inline int voxelBelow(double x) {
    const int truncated = int(x);
    return truncated - (x < double(truncated));
}

/// The voxel below @a x: its cell's first corner.
inline openvdb::Coord voxelBelow(const openvdb::Vec3d& x) {
    return openvdb::Coord(voxelBelow(x[0]), voxelBelow(x[1]), voxelBelow(x[2]));
}

/// One step of a trilinear blend, of a double or of lanes of them (each lane as a
/// double alone). In doubles, so that values near the float range's ends cannot overflow.
template <typename Lanes>
inline Lanes trilinearLerp(Lanes a, Lanes b, double s) {
    return (1.0 - s) * a + s * b;
}

/// The trilinear blend of eight corners, corner n at (n >> 2, n >> 1 & 1, n & 1)
/// (z fastest, as a leaf's voxels), at fractions @a t.
template <typename Lanes>
Lanes blendCorners(const Lanes (&corners)[8], const openvdb::Vec3d& t) {
    const auto lerp = trilinearLerp<Lanes>;  // a short name: the blend nests three deep
    Lanes alongY[2];
    for (int i = 0; i < 2; ++i) {
        const Lanes* pair = corners + 4 * i;
        alongY[i] = lerp(lerp(pair[0], pair[1], t[2]), lerp(pair[2], pair[3], t[2]), t[1]);
    }
    return lerp(alongY[0], alongY[1], t[0]);
}

/// The same for grid values, into out[0..channels). A colour's red and green share
/// two lanes and its blue takes a third: colour stills spent a third of their build
/// blending one channel at a time (docs/benchmarks.md, "Stacks of colours").
template <typename ValueT>
void blendTrilinearCorners(const ValueT (&corners)[8], const openvdb::Vec3d& t, float* out) {
    if constexpr (std::is_same_v<ValueT, openvdb::Vec3s>) {
        using Pair = double __attribute__((vector_size(16)));
        Pair redGreen[8], blue[8];
        for (int n = 0; n < 8; ++n) {
            redGreen[n] = Pair{corners[n][0], corners[n][1]};
            blue[n] = Pair{corners[n][2], 0.0};
        }
        const Pair rg = blendCorners(redGreen, t), b = blendCorners(blue, t);
        out[0] = float(rg[0]);
        out[1] = float(rg[1]);
        out[2] = float(b[0]);
    } else {
        double values[8];
        for (int n = 0; n < 8; ++n) values[n] = corners[n];
        out[0] = float(blendCorners(values, t));
    }
}

}  // namespace gvr
