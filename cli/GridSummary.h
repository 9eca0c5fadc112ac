/// @file GridSummary.h
/// @brief What `gvr info` reports about a grid.
#pragma once

#include <nlohmann/json.hpp>
#include <openvdb/openvdb.h>

#include <array>
#include <optional>
#include <string>

namespace gvr {

struct GridSummary {
    std::string name;
    std::string valueType;              ///< "float", "vec3s", ...
    std::string gridClass;              ///< "fog volume", "level set" or "unknown"
    openvdb::Coord dims{0, 0, 0};       ///< active bounding box, in voxels
    openvdb::Vec3d spacingMm{0.0};      ///< world length of each index axis
    double valueMin = 0, valueMax = 0;  ///< over active voxels (all components for vectors)
    std::uint64_t activeVoxels = 0;
    std::uint64_t memoryBytes = 0;  ///< in memory, as OpenVDB counts it
    /// The grid's metadata, typed: numbers as numbers, vectors as arrays.
    nlohmann::json metadata = nlohmann::json::object();
    /// world = affine * (i, j, k, 1): index space to world millimetres, the column
    /// form that NIfTI's sform and nibabel use. Unset for a non-linear transform.
    std::optional<std::array<std::array<double, 4>, 4>> affine;
};

GridSummary summarizeGrid(const openvdb::GridBase& grid);

nlohmann::json toJson(const GridSummary& summary);

/// Several indented lines for a terminal.
std::string toText(const GridSummary& summary);

}  // namespace gvr

namespace gvr {

/// "3.2 MiB"-style size for people.
std::string formatBytes(std::uint64_t bytes);

}  // namespace gvr
