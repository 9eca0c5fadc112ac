/// @file VoxelBrick.h
/// @brief A box of a grid's voxels copied into a dense array, for sampling it
/// trilinearly many times over: a stack build samples each block of its lattice
/// from one brick, where a trip through the tree for each sample (and eight where
/// its corners straddle leaves) took half the build (docs/benchmarks.md, "Stack
/// builds from dense bricks").
#pragma once

#include "render/RenderVolume.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace gvr {

template <typename GridT>
class VoxelBrick {
public:
    using ValueT = typename GridT::ValueType;
    using LeafT = typename GridT::TreeType::LeafNodeType;

    /// Copies the values of @a box (active or not; tiles and the background as
    /// they read) through @a accessor, leaf by leaf.
    template <typename Accessor>
    void fill(const Accessor& accessor, const openvdb::CoordBBox& box) {
        mMin = box.min();
        mDim = box.dim();
        mValues.resize(std::size_t(mDim.x()) * mDim.y() * mDim.z());
        constexpr int dim = int(LeafT::DIM);
        const auto leafStart = [](int v) { return v & ~(dim - 1); };  // floors negatives too
        for (int lx = leafStart(box.min().x()); lx <= box.max().x(); lx += dim) {
            for (int ly = leafStart(box.min().y()); ly <= box.max().y(); ly += dim) {
                for (int lz = leafStart(box.min().z()); lz <= box.max().z(); lz += dim) {
                    const openvdb::Coord origin(lx, ly, lz);
                    openvdb::CoordBBox part(origin, origin + openvdb::Coord(dim - 1));
                    part.intersect(box);
                    copyPart(accessor, origin, part);
                }
            }
        }
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

    /// Copies @a part, which lies in the leaf at @a origin: from its array, or one
    /// value throughout where the tree holds a tile or nothing there.
    template <typename Accessor>
    void copyPart(const Accessor& accessor, const openvdb::Coord& origin, const openvdb::CoordBBox& part) {
        const LeafT* leaf = accessor.probeConstLeaf(origin);
        const ValueT tile = leaf ? ValueT{} : accessor.getValue(origin);
        const int run = part.dim().z();
        for (int i = part.min().x(); i <= part.max().x(); ++i) {
            for (int j = part.min().y(); j <= part.max().y(); ++j) {
                const openvdb::Coord start(i, j, part.min().z());
                ValueT* to = mValues.data() + index(start);
                if (leaf) {
                    const ValueT* from = leaf->buffer().data() + LeafT::coordToOffset(start);
                    std::copy(from, from + run, to);
                } else {
                    std::fill(to, to + run, tile);
                }
            }
        }
    }

    openvdb::Coord mMin, mDim;
    std::vector<ValueT> mValues;  ///< z fastest, as a leaf's
};

}  // namespace gvr
