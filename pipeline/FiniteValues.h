/// @file FiniteValues.h
/// @brief Whether a grid holds only finite values: ingest refuses NaN and Inf in a
/// scan, and a .vdb read as it stands must meet the same rule before anything
/// samples, fits or renders it.
#pragma once

#include <openvdb/openvdb.h>

#include <optional>
#include <string>

namespace gvr {

/// @throw InputError naming @a name when the background, a tile or any voxel of
/// @a grid (active or not: samplers read both) is NaN or infinite, with how many
/// and where the first is.
/// @param region  if given, only the leaves and tiles that touch it
void requireFiniteValues(const openvdb::GridBase& grid, const std::string& name,
                         const std::optional<openvdb::CoordBBox>& region = std::nullopt);

}  // namespace gvr
