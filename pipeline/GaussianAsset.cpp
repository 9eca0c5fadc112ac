#include "pipeline/GaussianAsset.h"

#include "pipeline/Error.h"
#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gvr {

void keepOnly(GaussianAsset& asset, const std::vector<bool>& keep) {
    asset.params.keepOnly(keep);
    asset.residual.reset();  // it corrects the field of every Gaussian, and some are gone
    if (asset.labels.empty()) return;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keep.size(); ++i) {
        if (keep[i]) asset.labels[kept++] = asset.labels[i];
    }
    asset.labels.resize(kept);
}

void keepStrongest(GaussianAsset& asset, std::size_t keepCount) {
    const GaussianParameters& params = asset.params;
    std::vector<float> peak(params.count());
    for (std::size_t i = 0; i < params.count(); ++i) peak[i] = peakAmplitude(params, i);
    std::vector<std::size_t> order(params.count());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return peak[a] > peak[b]; });
    std::vector<bool> keep(params.count(), false);
    for (std::size_t k = 0; k < keepCount; ++k) keep[order[k]] = true;
    keepOnly(asset, keep);
}

GaussianAsset withLabels(const GaussianAsset& asset, const std::vector<int>& shown) {
    if (asset.labels.empty()) return asset;
    GaussianAsset subset = asset;
    std::vector<bool> keep(asset.labels.size());
    for (std::size_t i = 0; i < keep.size(); ++i) {
        keep[i] = std::binary_search(shown.begin(), shown.end(), asset.labels[i]);
    }
    keepOnly(subset, keep);
    subset.labelTable.names.clear();
    for (int id : shown) subset.labelTable.names[id] = asset.labelTable.nameOf(id);
    return subset;
}

GaussianAsset selectStructures(const GaussianAsset& asset, const std::string& show, const std::string& hide,
                               const std::string& path) {
    if (show.empty() && hide.empty()) return asset;
    if (asset.labelTable.names.empty()) {
        throw InputError(path, "has no structures to show or hide; fit it by structure (`labels`)");
    }
    return withLabels(asset, shownLabels(asset.labelTable, show, hide));
}

}  // namespace gvr
