#include "pipeline/AssetProbe.h"

namespace gvr {

AssetProbe::AssetProbe(const GaussianAsset& asset)
    : mField(asset.params, asset.cutoffSigmas), mMapping(asset.mapping) {}

AssetProbe::Sample AssetProbe::at(const std::array<double, 3>& index) {
    const float x[3] = {float(index[0]), float(index[1]), float(index[2])};
    float normalised[3];
    mField.evaluate(x, normalised, mHits);
    Sample sample;
    for (int c = 0; c < mField.channels(); ++c) sample.value[c] = mMapping.toPhysical(normalised[c], c);
    sample.gaussians = mHits.size();
    return sample;
}

}  // namespace gvr
