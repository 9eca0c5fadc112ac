/// @file TeamFit.h
/// @brief A bricked fit run by a BrickTeam: all the bricks in this process or
/// across the ranks of an mpirun, merged on rank 0; or one brick of a job array.
#pragma once

#include "pipeline/FieldAccuracy.h"
#include "workflow/BrickTeam.h"
#include "workflow/BrickedFit.h"

#include <functional>

namespace gvr {

/// The observer of brick @a brick's fit, made as that fit starts and dropped as it
/// ends; only rank 0 asks for them. May be empty.
using BrickObservers = std::function<FitObserver(std::size_t brick)>;

/// One brick's line in the merged report.
struct BrickReport {
    std::size_t brick = 0;
    std::size_t budget = 0;  ///< the Gaussians the plan gave it
    BrickRun run;
};

/// A bricked fit as rank 0 reports it.
struct TeamFitResult {
    BudgetedFitResult result;
    std::vector<BrickReport> bricks;  ///< in brick order
    double mergeSeconds = 0.0;
    std::vector<Brick> layout;  ///< the plan's bricks, for seam errors
    std::vector<int> owners;    ///< the rank that fitted each brick
};

/// Voxels this close to a face between bricks count as seam voxels in fit reports.
constexpr int kSeamWidth = 4;

/// This process's share of the bricks (all of them alone, or its rank's), merged on
/// rank 0. Other ranks get only the layout and owners.
/// @throw InputError naming the brick and rank of the first brick that failed.
TeamFitResult fitAllBricks(const BrickTeam& team, const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                           const std::string& name, const BudgetedFitOptions& options, const BrickOptions& bricks,
                           const BrickObservers& observers = {});

/// The error of the merged asset as saved (@a saved: its bytes, in every rank), with
/// the voxels near brick faces marked. Each rank measures the cores of the bricks
/// it fitted, so it reads no other part of the grid; the result, on rank 0 only,
/// is the same to the bit for any number of ranks.
FieldAccuracy measureAcrossTeam(const BrickTeam& team, const std::string& saved, const VolumeTarget& target,
                                const TeamFitResult& fit, const ProgressFn& progress = {});

/// Brick @a index of @a bricks alone, as a part asset for a job array's merge.
/// @throw InputError naming `brick` when @a index is not below the brick count.
GaussianAsset fitOneBrick(const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target, const std::string& name,
                          const BudgetedFitOptions& options, const BrickOptions& bricks, std::size_t index,
                          const FitObserver& observer = {});

}  // namespace gvr
