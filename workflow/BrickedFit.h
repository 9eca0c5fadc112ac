/// @file BrickedFit.h
/// @brief `gvr fit --bricks`: a fit cut into bricks (pipeline/Bricks.h) whose
/// results travel as part assets and merge into one ordinary asset.
///
/// Every process that fits bricks makes the same plan from the same grid and
/// options, fits the bricks it is given, and turns each into a part: a valid asset
/// of the brick's Gaussians, stored finely enough (16-bit attributes, means on a
/// 1/512-voxel lattice) that the merge's own rounding decides the result. The
/// merge concatenates the parts in brick order and trims the whole to the byte
/// budget. A single process, MPI ranks and a Slurm job array therefore give the
/// same asset byte for byte.
#pragma once

#include "pipeline/Bricks.h"
#include "workflow/FitToBudget.h"

#include <string>
#include <vector>

namespace gvr {

struct BrickOptions {
    std::size_t count = 1;  ///< bricks in all
    int halo = kDefaultBrickHalo;
};

/// What every brick of one fit shares.
struct BrickPlan {
    GaussianAsset skeleton;      ///< the merged asset without its Gaussians
    FitSettings settings;        ///< checked; settings.seconds is each process's own budget
    std::uint64_t maxBytes = 0;  ///< the merged asset's byte budget (0: an exact count)
    openvdb::Coord lattice;
    int halo = kDefaultBrickHalo;
    std::vector<Brick> bricks;
};

/// @throw InputError for options that fitToBudget() refuses, and for a brick count
///        that the volume's leaves cannot take.
BrickPlan planBrickedFit(const VolumeTarget& target, const std::string& name, const BudgetedFitOptions& options,
                         const BrickOptions& bricks);

/// A process's share of its time budget for brick @a index, when it fits
/// @a mine (brick indices): in proportion to their Gaussians.
double brickSeconds(const BrickPlan& plan, const std::vector<std::size_t>& mine, std::size_t index);

/// How the fit of one brick went, as its part records it for the merged report.
struct BrickRun {
    int rank = 0;  ///< of the team that fitted it
    std::size_t gaussians = 0, iterations = 0, pruned = 0, respawned = 0, solveIterations = 0;
    double seconds = 0, solveSeconds = 0;
    double rankPeakRssMiB = 0;  ///< the fitting process's peak so far
};

/// Fits brick @a index of @a plan with a time budget of @a seconds (ignored with an
/// iteration budget) and returns it as a part asset, with its BrickRun recorded.
GaussianAsset fitBrickPart(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const BrickPlan& plan,
                           std::size_t index, double seconds, const FitObserver& observer = {}, int rank = 0);

/// The run that @a part records.
/// @throw InputError naming @a name when it records none, or a corrupt one.
BrickRun brickRunOf(const GaussianAsset& part, const std::string& name);

/// Which brick of how many @a part holds (from its "brick" record).
/// @throw InputError naming @a name when @a part is not a brick part.
std::pair<std::size_t, std::size_t> brickOfPart(const GaussianAsset& part, const std::string& name);

/// One asset from the parts of all bricks of a fit (any order; @a names name them
/// in errors), within the plan's byte budget. @a dropped gets the Gaussians dropped
/// to fit it.
/// @throw InputError naming a part that is not a brick part, comes from another fit
///        or another volume, or repeats a brick, or naming the missing bricks.
GaussianAsset mergeBrickParts(std::vector<GaussianAsset> parts, const std::vector<std::string>& names,
                              std::size_t* dropped = nullptr);

}  // namespace gvr
