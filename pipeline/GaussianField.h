/// @file GaussianField.h
/// @brief The truncated Gaussian field f(x) = sum_i amplitude_i exp(-q_i(x)/2), ready to
/// evaluate anywhere in index space.
#pragma once

#include "pipeline/GaussianBvh.h"
#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace gvr {

class GaussianField {
public:
    GaussianField() = default;
    GaussianField(const GaussianParameters& params, float cutoffSigmas, bool fastBuild = false) {
        rebuild(params, cutoffSigmas, fastBuild);
    }

    /// Activates every Gaussian and rebuilds the BVH over their truncated bounds,
    /// each grown by @a slackVoxels plus @a slackFraction of its half-extent, so
    /// that small moves need no rebuild (see update()).
    void rebuild(const GaussianParameters& params, float cutoffSigmas, bool fastBuild = false, float slackVoxels = 0.0f,
                 float slackFraction = 0.0f);

    /// Re-activates the Gaussians of @a params (the same count as at the last
    /// rebuild) and keeps the BVH. Queries stay exact because every Gaussian's
    /// truncated bounds must still lie inside its box in the BVH.
    /// @return false when one has left its box or the count changed: rebuild()
    ///         then, before evaluating (the field may be half updated).
    bool update(const GaussianParameters& params);

    /// Re-activates Gaussian @a index of @a params (the same count as at the last
    /// rebuild) and leaves the BVH as it was, even where the Gaussian has left its
    /// box: for callers that follow the moves themselves (BlockBins::follow), never
    /// for queries of the BVH. Calls for different Gaussians may run at the same time.
    void reactivate(const GaussianParameters& params, std::size_t index) {
        mGaussians[index] = activate(params, index);
    }

    /// f at @a x into value[0..channels). @a hits is scratch space, one per thread;
    /// it is left holding the indices of the Gaussians that reach x.
    void evaluate(const float x[3], float* value, std::vector<std::uint32_t>& hits) const {
        bvh().query(x, hits);
        std::sort(hits.begin(), hits.end());  // a fixed summation order
        for (int c = 0; c < mChannels; ++c) value[c] = 0.0f;
        for (std::uint32_t index : hits) accumulateValue(mGaussians[index], x, mCutoff2, mChannels, value);
    }

    int channels() const { return mChannels; }
    float cutoff2() const { return mCutoff2; }
    float cutoffSigmas() const { return mCutoffSigmas; }
    const std::vector<ActiveGaussian>& gaussians() const { return mGaussians; }
    /// @throw std::logic_error after releaseBvh(), until the next rebuild().
    const GaussianBvh& bvh() const {
        if (mBvh.size() != mGaussians.size())
            throw std::logic_error("GaussianField: its BVH was released; rebuild() first");
        return mBvh;
    }

    /// Frees the BVH, about 250 bytes a Gaussian, for a caller that has binned the
    /// Gaussians with it and asks its bins from then on (the fit). Until the next
    /// rebuild(), evaluate(), bvh() and update() throw std::logic_error.
    void releaseBvh() { mBvh.clear(); }
    /// Frees every Gaussian and the BVH: an empty field until the next rebuild().
    void clear() {
        std::vector<ActiveGaussian>().swap(mGaussians);
        mBvh.clear();
    }

private:
    int mChannels = 1;
    float mCutoffSigmas = kDefaultCutoffSigmas;
    float mCutoff2 = kDefaultCutoffSigmas * kDefaultCutoffSigmas;
    std::vector<ActiveGaussian> mGaussians;
    GaussianBvh mBvh;
};

}  // namespace gvr
