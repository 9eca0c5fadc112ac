#include "pipeline/Pruning.h"

#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <cmath>

namespace gvr {

PruneResult pruneAndRespawn(GaussianParameters& params, Adam& adam, double threshold,
                            const std::vector<RespawnSite>& sites) {
    const std::size_t count = params.count();
    std::vector<bool> keep(count, true);
    PruneResult result;
    for (std::size_t i = 0; i < count; ++i) {
        if (peakAmplitude(params, i) < threshold) {
            keep[i] = false;
            ++result.removed;
        }
    }
    if (result.removed == 0) return result;
    params.keepOnly(keep);
    adam.keepOnly(keep);

    result.respawned = std::min(result.removed, sites.size());
    // Appended within the capacity keepOnly() left, so that no second copy of every
    // Gaussian is made: pruning runs at the fit's peak memory.
    GaussianParameters respawned(result.respawned, params.channels);
    for (std::size_t s = 0; s < result.respawned; ++s) {
        std::copy_n(sites[s].position.data(), 3, respawned.at(kMeans, s));
        respawned.at(kRotations, s)[0] = 1.0f;
        // colour = residual / opacity, with opacity 1/2
        for (int c = 0; c < params.channels; ++c) respawned.at(kColours, s)[c] = 2.0f * sites[s].residual[c];
    }
    params.append(respawned);
    adam.grow(params.count());
    return result;
}

}  // namespace gvr
