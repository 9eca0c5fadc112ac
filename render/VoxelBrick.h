/// @file VoxelBrick.h
/// @brief A box of a grid's voxels copied into a dense array, for sampling it
/// trilinearly many times over: a stack build samples each block of its lattice
/// from one brick, where a trip through the tree for each sample (and eight where
/// its corners straddle leaves) took much of the build.
#pragma once

#include "pipeline/LatticeSampler.h"
#include "render/RenderVolume.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
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
        const openvdb::Coord base = voxelBelow(x);
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

    /// Where a row of samples falls along one grid axis: for each, a voxel and the
    /// fraction beyond it.
    struct Steps {
        int count = 0;
        std::array<int, kBlockDim> base;
        std::array<double, kBlockDim> t;
    };

    /// trilinearAt at each sample (a, b, c) of @a x by @a y by @a z, which run along
    /// the grid's axes, into @a out(a, b, c). The same to the bit, with the lerps
    /// that samples share done once: along z for each column of voxels the samples
    /// read, then along y, then along x, in blendTrilinearCorners' order.
    template <typename Out>
    void trilinearAlongAxes(const Steps& x, const Steps& y, const Steps& z, Out out) const {
        constexpr int channels = std::is_same_v<ValueT, openvdb::Vec3s> ? 3 : 1;
        const auto [x0, x1] = reached(x);
        const auto [y0, y1] = reached(y);
        const int nx = x1 - x0 + 1, ny = y1 - y0 + 1;
        thread_local std::vector<double> alongZ, alongY;  // per thread: the build's hot path
        alongZ.resize(std::size_t(nx) * ny * z.count * channels);
        alongY.resize(std::size_t(nx) * y.count * z.count * channels);
        double* at = alongZ.data();
        for (int gx = x0; gx <= x1; ++gx) {
            for (int gy = y0; gy <= y1; ++gy) {
                for (int c = 0; c < z.count; ++c) {
                    const ValueT* pair = mValues.data() + index(openvdb::Coord(gx, gy, z.base[c]));
                    for (int ch = 0; ch < channels; ++ch) {
                        *at++ = trilinearLerp(channelOf(pair[0], ch), channelOf(pair[1], ch), z.t[c]);
                    }
                }
            }
        }
        const std::size_t zRow = std::size_t(z.count) * channels;
        at = alongY.data();
        for (int gx = x0; gx <= x1; ++gx) {
            for (int b = 0; b < y.count; ++b) {
                const double* lo = alongZ.data() + (std::size_t(gx - x0) * ny + (y.base[b] - y0)) * zRow;
                for (std::size_t n = 0; n < zRow; ++n) *at++ = trilinearLerp(lo[n], lo[n + zRow], y.t[b]);
            }
        }
        const std::size_t yPlane = std::size_t(y.count) * zRow;
        for (int a = 0; a < x.count; ++a) {
            const double* lo = alongY.data() + std::size_t(x.base[a] - x0) * yPlane;
            for (int b = 0; b < y.count; ++b) {
                for (int c = 0; c < z.count; ++c) {
                    float* sample = out(a, b, c);
                    const std::size_t n = b * zRow + c * channels;
                    for (int ch = 0; ch < channels; ++ch) {
                        sample[ch] = float(trilinearLerp(lo[n + ch], lo[n + ch + yPlane], x.t[a]));
                    }
                }
            }
        }
    }

private:
    /// The voxels @a steps read: each base and the one after it.
    static std::pair<int, int> reached(const Steps& steps) {
        const auto [lo, hi] = std::minmax_element(steps.base.begin(), steps.base.begin() + steps.count);
        return {*lo, *hi + 1};
    }

    std::size_t index(const openvdb::Coord& ijk) const {
        const openvdb::Coord d = ijk - mMin;
        return (std::size_t(d.x()) * mDim.y() + d.y()) * mDim.z() + d.z();
    }

    openvdb::Coord mMin, mDim;
    std::vector<ValueT> mValues;  ///< z fastest, as a leaf's (LayoutZYX)
};

}  // namespace gvr
