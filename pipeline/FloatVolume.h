/// @file FloatVolume.h
/// @brief A dense block of float samples and its place in the world: what the
/// quality metrics compare, and what a grid or an image becomes for them.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace gvr {

struct FloatVolume {
    openvdb::Coord dims{0, 0, 0};  ///< samples along i, j, k; an image has dims.z() == 1
    int channels = 1;
    /// Physical values, i fastest, then j, then k, channels interleaved.
    std::vector<float> values;
    /// One flag per voxel (1 = foreground), or empty when the source had no notion
    /// of one. A grid's active voxels are its foreground.
    std::vector<std::uint8_t> foreground;
    /// Index space to world millimetres, OpenVDB's row-vector convention.
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();

    FloatVolume() = default;
    FloatVolume(const openvdb::Coord& dims, int channels);  ///< zero-filled

    std::size_t voxelCount() const { return std::size_t(dims.x()) * dims.y() * dims.z(); }
    std::size_t indexOf(int i, int j, int k) const { return (std::size_t(k) * dims.y() + j) * dims.x() + i; }
    float* at(int i, int j, int k) { return values.data() + indexOf(i, j, k) * channels; }
    const float* at(int i, int j, int k) const { return values.data() + indexOf(i, j, k) * channels; }
};

/// The voxels a grid stands for: the source's full box when gvr ingested (or
/// exported) it, else the bounding box of its active voxels.
openvdb::CoordBBox volumeBox(const openvdb::GridBase& grid);

/// The values of a float, double or Vec3s grid over @a box (inactive voxels give
/// the value they hold, the background for grids gvr wrote), with the grid's
/// active voxels as foreground. worldFromIndex puts sample (0, 0, 0) at box.min().
/// @throw InputError naming the grid for any other value type.
FloatVolume sampleGrid(const openvdb::GridBase& grid, const openvdb::CoordBBox& box);

/// @a source sampled trilinearly at the world positions of the voxel centres of a
/// lattice of @a dims placed by @a worldFromIndex. Positions outside @a source take
/// its nearest edge voxel, which for medical volumes is background.
FloatVolume resampleTrilinear(const FloatVolume& source, const openvdb::Coord& dims,
                              const openvdb::math::Mat4d& worldFromIndex);

}  // namespace gvr
