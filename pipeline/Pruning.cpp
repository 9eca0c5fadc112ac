#include "pipeline/Pruning.h"

#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <cmath>

namespace gvr {

std::size_t negligibleCount(const GaussianParameters& params, double threshold) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < params.count(); ++i) count += peakAmplitude(params, i) < threshold;
    return count;
}

PruneResult pruneAndRespawn(GaussianParameters& params, Adam& adam, double threshold,
                            const std::vector<RespawnSite>& sites) {
    std::vector<std::pair<float, std::size_t>> negligible;
    for (std::size_t i = 0; i < params.count(); ++i) {
        const float peak = peakAmplitude(params, i);
        if (peak < threshold) negligible.emplace_back(peak, i);
    }
    PruneResult result;
    result.removed = std::min(negligible.size(), sites.size());
    if (result.removed == 0) return result;
    std::partial_sort(negligible.begin(), negligible.begin() + std::ptrdiff_t(result.removed), negligible.end());
    std::vector<bool> keep(params.count(), true);
    for (std::size_t k = 0; k < result.removed; ++k) keep[negligible[k].second] = false;
    params.keepOnly(keep);
    adam.keepOnly(keep);
    result.respawned = addGaussiansAt(params, adam, sites, result.removed);
    return result;
}

std::size_t addGaussiansAt(GaussianParameters& params, Adam& adam, const std::vector<RespawnSite>& sites,
                           std::size_t most) {
    const std::size_t count = std::min(most, sites.size());
    // After pruning, appended within the capacity keepOnly() left, so that no second
    // copy of every Gaussian is made: pruning runs at the fit's peak memory.
    GaussianParameters added(count, params.channels);
    for (std::size_t s = 0; s < count; ++s) {
        std::copy_n(sites[s].position.data(), 3, added.at(kMeans, s));
        added.at(kRotations, s)[0] = 1.0f;
        // colour = residual / opacity, with opacity 1/2
        for (int c = 0; c < params.channels; ++c) added.at(kColours, s)[c] = 2.0f * sites[s].residual[c];
    }
    params.append(added);
    adam.grow(params.count());
    return count;
}

}  // namespace gvr
