/// @file LabelBudget.h
/// @brief How many Gaussians each structure gets: in proportion to its voxels, with
/// a floor, so that a small structure is not starved by a large one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gvr {

/// Below this many Gaussians a structure is not worth fitting (unless it has fewer voxels).
constexpr std::size_t kStructureFloor = 16;

/// Splits exactly @a total Gaussians: min(floor, voxels) to each structure first,
/// the rest in proportion to voxel counts (largest remainders get the odd ones).
/// @throw InputError when @a total cannot cover the floors.
std::vector<std::size_t> splitBudget(std::size_t total, const std::vector<std::uint64_t>& voxels,
                                     std::size_t floor = kStructureFloor);

/// @a gaussiansPerVoxel times each structure's voxels, rounded, at least the floor.
/// Each budget depends on its own structure only, so a structure fitted with or
/// without the others gets the same one.
std::vector<std::size_t> proportionalBudgets(double gaussiansPerVoxel, const std::vector<std::uint64_t>& voxels,
                                             std::size_t floor = kStructureFloor);

}  // namespace gvr
