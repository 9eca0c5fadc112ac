/// @file Pruning.h
/// @brief Removes negligible Gaussians and re-seeds the freed budget where the error is largest.
///
/// Kept apart from the optimiser loop (gsplat's "strategy"): it edits the
/// parameters and the Adam moments together.
#pragma once

#include "pipeline/Adam.h"
#include "pipeline/GaussianParameters.h"

#include <array>
#include <vector>

namespace gvr {

/// A voxel whose residual (target - field) is large: a place for a new Gaussian.
struct RespawnSite {
    std::array<float, 3> position;
    std::array<float, 3> residual;  ///< per channel, normalised units
};

struct PruneResult {
    std::size_t removed = 0;
    std::size_t respawned = 0;
};

/// How many Gaussians are negligible to pruneAndRespawn(): the most it moves.
std::size_t negligibleCount(const GaussianParameters& params, double threshold);

/// Moves negligible Gaussians, those whose peak contribution max_c |opacity *
/// colour_c| is below @a threshold, to the sites: the weakest first, one a site,
/// so the count never falls (ct-head at 40:1 once lost 22,000 late in the fit,
/// where few voxels had a residual worth a Gaussian, and wrote 42.6:1). Each
/// newcomer is one voxel wide, opacity 1/2, with the colour that fills its site's
/// residual.
PruneResult pruneAndRespawn(GaussianParameters& params, Adam& adam, double threshold,
                            const std::vector<RespawnSite>& sites);

/// Adds one Gaussian at each of the first @a most sites, as pruneAndRespawn() does,
/// with Adam moments of zero; returns how many it added.
std::size_t addGaussiansAt(GaussianParameters& params, Adam& adam, const std::vector<RespawnSite>& sites,
                           std::size_t most);

}  // namespace gvr
