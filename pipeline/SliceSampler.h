/// @file SliceSampler.h
/// @brief Sparse pixels on a randomly oriented plane through the volume, for the slice loss.
#pragma once

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <vector>

namespace gvr {

/// Draws a plane with a uniformly random normal through a point chosen uniformly
/// inside @a box (index space), then @a pixels points uniformly over the plane's
/// part inside the box. Returns the points (fewer than @a pixels may fall inside
/// when the plane only grazes the box; at least one always does).
std::vector<std::array<float, 3>> drawSlicePoints(const openvdb::CoordBBox& box, std::size_t pixels,
                                                  std::uint64_t seed);

}  // namespace gvr
