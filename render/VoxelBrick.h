/// @file VoxelBrick.h
/// @brief A box of a grid's voxels copied into a dense array, for sampling it
/// trilinearly many times over: a stack build samples each block of its lattice
/// from one brick, where a trip through the tree for each sample (and eight where
/// its corners straddle leaves) took half the build (docs/benchmarks.md, "Stack
/// builds from dense bricks").
#pragma once

#include "render/RenderVolume.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <cmath>
#include <vector>

namespace gvr {

template <typename GridT>
class VoxelBrick {
public:
    using ValueT = typename GridT::ValueType;

    /// Copies the values of @a box from @a grid (active or not; tiles and the
    /// background as they read).
    void fill(const GridT& grid, const openvdb::CoordBBox& box) {
        mMin = box.min();
        mDim = box.dim();
        mValues.resize(std::size_t(mDim.x()) * mDim.y() * mDim.z());
        openvdb::tools::Dense<ValueT, openvdb::tools::LayoutZYX> dense(box, mValues.data());
        grid.tree().root().copyToDense(box, dense);
    }

    /// The box filled.
    openvdb::CoordBBox box() const { return {mMin, mMin + mDim - openvdb::Coord(1)}; }

    /// As GridRenderVolume::trilinear, to the bit: @a x with its eight corners must
    /// lie in box().
    void trilinear(const openvdb::Vec3d& x, float* out) const {
        const openvdb::Coord base(int(std::floor(x[0])), int(std::floor(x[1])), int(std::floor(x[2])));
        trilinearAt(base, x - base.asVec3d(), out);
    }

    /// The same at @a base plus fractions @a t (each in [0, 1)).
    void trilinearAt(const openvdb::Coord& base, const openvdb::Vec3d& t, float* out) const {
        const ValueT* first = mValues.data() + index(base);
        const std::size_t stepX = std::size_t(mDim.y()) * mDim.z(), stepY = std::size_t(mDim.z());
        ValueT corners[8];
        for (int n = 0; n < 8; ++n) corners[n] = first[(n >> 2) * stepX + (n >> 1 & 1) * stepY + (n & 1)];
        blendTrilinearCorners(corners, t, out);
    }

private:
    std::size_t index(const openvdb::Coord& ijk) const {
        const openvdb::Coord d = ijk - mMin;
        return (std::size_t(d.x()) * mDim.y() + d.y()) * mDim.z() + d.z();
    }

    openvdb::Coord mMin, mDim;
    std::vector<ValueT> mValues;  ///< z fastest, as a leaf's (LayoutZYX)
};

}  // namespace gvr
