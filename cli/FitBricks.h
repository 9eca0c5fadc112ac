/// @file FitBricks.h
/// @brief `gvr fit` in bricks: all of them in this process or across the ranks of
/// an mpirun (--bricks N), or one of them for a job array (--brick I --of N).
#pragma once

#include "BrickTeam.h"
#include "BrickedFit.h"
#include "FieldAccuracy.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>

namespace gvr {

struct BrickFlags {
    std::size_t count = 0;  ///< --bricks, or --of with --brick
    int halo = kDefaultBrickHalo;
    std::optional<std::size_t> only;  ///< --brick I: fit this one and write its part

    bool any() const { return count > 0; }
};

void addBrickFlags(CLI::App& command, BrickFlags& flags);

/// A bricked fit as `gvr fit` reports it.
struct BrickedFitResult {
    CompressResult result;
    nlohmann::json bricks = nlohmann::json::array();  ///< a row per brick: rank, Gaussians, time, memory
    double mergeSeconds = 0.0;
    std::vector<Brick> layout;  ///< the plan's bricks, for seam errors
    std::vector<int> owners;    ///< the rank that fitted each brick
};

/// Voxels this close to a face between bricks count as seam voxels in fit reports.
constexpr int kSeamWidth = 4;

/// --bricks N: this process's share of the bricks (all of them, or its rank's under
/// mpirun), merged on rank 0. Other ranks get only the layout and owners.
/// @throw InputError naming the brick and rank of the first brick that failed.
BrickedFitResult fitAllBricks(const BrickTeam& team, const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                              const std::string& name, const CompressOptions& options, const BrickFlags& flags,
                              bool progress);

/// The error of the merged asset as saved (@a saved: its bytes, in every rank), with
/// the voxels near brick faces marked. Each rank measures the cores of the bricks
/// it fitted, so it reads no other part of the grid; the result, on rank 0 only,
/// is the same to the bit for any number of ranks.
FieldAccuracy measureAcrossTeam(const BrickTeam& team, const std::string& saved, const VolumeTarget& target,
                              const BrickedFitResult& fit, bool progress);

/// --brick I --of N: fits brick I and returns its part asset, for writeAsset().
GaussianAsset fitOneBrick(const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                          const std::string& name, const CompressOptions& options, const BrickFlags& flags,
                          bool progress);

}  // namespace gvr
