#include "pipeline/GaussianField.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace gvr {

void GaussianField::rebuild(const GaussianParameters& params, float cutoffSigmas, bool fastBuild, float slackVoxels,
                            float slackFraction) {
    mChannels = params.channels;
    mCutoffSigmas = cutoffSigmas;
    mCutoff2 = cutoffSigmas * cutoffSigmas;
    const std::size_t count = params.count();
    mGaussians.resize(count);
    std::vector<Box> boxes(count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t i) {
        mGaussians[i] = activate(params, i);
        Box& box = boxes[i];
        truncatedBounds(mGaussians[i], cutoffSigmas, box.lower.data(), box.upper.data());
        for (int a = 0; a < 3; ++a) {
            const float grow = slackVoxels + slackFraction * 0.5f * (box.upper[a] - box.lower[a]);
            box.lower[a] -= grow;
            box.upper[a] += grow;
        }
    });
    mBvh.build(std::move(boxes), fastBuild);
}

bool GaussianField::update(const GaussianParameters& params) {
    const std::size_t count = params.count();
    if (count != mGaussians.size() || params.channels != mChannels) return false;
    const std::vector<Box>& boxes = bvh().boxes();
    // In place: a second array would be as large as the field (the fit's peak memory).
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, count), true,
        [&](const tbb::blocked_range<std::size_t>& range, bool ok) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                mGaussians[i] = activate(params, i);
                float lower[3], upper[3];
                truncatedBounds(mGaussians[i], mCutoffSigmas, lower, upper);
                for (int a = 0; a < 3; ++a) {
                    ok = ok && lower[a] >= boxes[i].lower[a] && upper[a] <= boxes[i].upper[a];
                }
            }
            return ok;
        },
        [](bool a, bool b) { return a && b; });
}

}  // namespace gvr
