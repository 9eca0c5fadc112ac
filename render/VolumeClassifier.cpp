#include "render/VolumeClassifier.h"

#include "pipeline/LowerCase.h"

namespace gvr {

Classifier volumeClassifier(const RenderVolume& volume, const TransferFunction& tf) {
    return Classifier(tf, volume.channels(), 1.0 / volume.valueMax());
}

TransferFunction presetFor(const RenderVolume& volume, const std::string& preset, std::string* mismatch) {
    const VolumeStatistics statistics = volume.statistics();
    const std::string name = preset.empty() ? defaultPreset(volume.channels(), statistics) : lowerCase(preset);
    TransferFunction tf = presetTransferFunction(name, statistics);
    if (mismatch) *mismatch = presetMismatch(name, volume.channels(), statistics);
    return tf;
}

}  // namespace gvr
