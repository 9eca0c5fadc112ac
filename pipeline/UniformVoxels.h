/// @file UniformVoxels.h
/// @brief Voxels drawn uniformly from a box: held-out sets and level checks.
#pragma once

#include <openvdb/openvdb.h>

#include <cstdint>
#include <vector>

namespace gvr {

/// @a count voxels of @a box, each uniformly and independently (repeats possible);
/// the same seed gives the same voxels.
std::vector<openvdb::Coord> drawUniformVoxels(const openvdb::CoordBBox& box, std::size_t count, std::uint64_t seed);

}  // namespace gvr
