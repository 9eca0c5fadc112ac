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
    const std::size_t kept = params.count();
    GaussianParameters grown(kept + result.respawned, params.channels);
    for (int g = 0; g < kGroupCount; ++g) std::copy(params.values[g].begin(), params.values[g].end(), grown.values[g].begin());
    for (std::size_t s = 0; s < result.respawned; ++s) {
        const std::size_t i = kept + s;
        std::copy_n(sites[s].position.data(), 3, grown.at(kMeans, i));
        grown.at(kRotations, i)[0] = 1.0f;
        // colour = residual / opacity, with opacity 1/2
        for (int c = 0; c < params.channels; ++c) grown.at(kColours, i)[c] = 2.0f * sites[s].residual[c];
    }
    params = std::move(grown);
    adam.grow(params.count());
    return result;
}

}  // namespace gvr
