#include "GaussianField.h"

#include <tbb/parallel_for.h>

namespace gvr {

void GaussianField::rebuild(const GaussianParameters& params, float cutoffSigmas, bool fastBuild) {
    mChannels = params.channels;
    mCutoff2 = cutoffSigmas * cutoffSigmas;
    const std::size_t count = params.count();
    mGaussians.resize(count);
    std::vector<Box> boxes(count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
        mGaussians[i] = activate(params, i);
        truncatedBounds(mGaussians[i], cutoffSigmas, boxes[i].lower.data(), boxes[i].upper.data());
    });
    mBvh.build(std::move(boxes), fastBuild);
}

}  // namespace gvr
