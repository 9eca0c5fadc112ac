#include "render/StyledLayers.h"

#include "pipeline/Error.h"

#include <algorithm>

namespace gvr {

StyledLayers styledLayers(const GaussianAsset& asset, const std::map<std::string, LabelStyle>& styles,
                          const Classifier& base, float minScaleVoxels, const std::string& stylesName) {
    StyledLayers result;
    const auto addLayer = [&](const std::vector<int>& ids, Classifier classifier) {
        result.volumes.push_back(std::make_unique<GaussianRenderVolume>(withLabels(asset, ids), minScaleVoxels));
        result.layers.push_back({result.volumes.back().get(), std::move(classifier)});
    };
    std::vector<int> plain;
    for (const auto& [id, name] : asset.labelTable.names) plain.push_back(id);
    for (const auto& [key, style] : styles) {
        if (style.colour && base.channels() != 1) {
            throw InputError(stylesName,
                             "colours apply to grey assets; RGB structures keep their own (opacity applies)");
        }
        for (int id : selectLabels(asset.labelTable, key, stylesName)) {
            plain.erase(std::remove(plain.begin(), plain.end(), id), plain.end());
            addLayer({id}, Classifier(styledTransferFunction(base.transferFunction(), style), base.channels(),
                                      base.colourScale()));
        }
    }
    if (!plain.empty()) addLayer(plain, base);
    return result;
}

}  // namespace gvr
