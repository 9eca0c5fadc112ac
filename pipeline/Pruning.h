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

/// Removes the Gaussians whose peak contribution max_c |opacity * colour_c| is
/// below @a threshold, then adds one Gaussian per site (up to the number removed):
/// one voxel wide, opacity 1/2, and the colour that fills the site's residual.
PruneResult pruneAndRespawn(GaussianParameters& params, Adam& adam, double threshold,
                            const std::vector<RespawnSite>& sites);

}  // namespace gvr
