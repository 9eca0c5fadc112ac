/// @file Adam.h
/// @brief Adam with one learning rate per parameter group, a Gaussian at a time.
#pragma once

#include "pipeline/GaussianParameters.h"

#include <array>
#include <cstdint>

namespace gvr {

struct AdamSettings {
    double beta1 = 0.9;
    double beta2 = 0.999;
    double epsilon = 1e-12;
};

class Adam {
public:
    Adam(std::size_t count, int channels, const AdamSettings& settings = {});

    /// Starts a step: params -= rate[g] * mhat / (sqrt(vhat) + eps) per group g, for
    /// each Gaussian that update() is then called for.
    void beginStep(const std::array<double, kGroupCount>& rates);
    /// The share of the step begun last of Gaussians [begin, end), whose gradient is
    /// @a gradient (Gaussian begin + i at its index i). A Gaussian whose gradient or
    /// any result is not finite keeps its parameters and moments, and gets
    /// updated[i] = 0; the others get 1. Calls for disjoint ranges may run at the
    /// same time.
    void update(GaussianParameters& params, const GaussianParameters& gradient, std::size_t begin, std::size_t end,
                std::uint8_t* updated);

    /// Drops the moments of removed Gaussians, in step with params.keepOnly().
    void keepOnly(const std::vector<bool>& keep);
    /// Reorders the moments, in step with params.permute().
    void permute(const std::vector<std::uint32_t>& order);
    /// Adds zeroed moments for Gaussians appended to the parameters.
    void grow(std::size_t count);

private:
    AdamSettings mSettings;
    GaussianParameters mFirst, mSecond;
    std::size_t mSteps = 0;
    std::array<float, kGroupCount> mRate{};  ///< this step's, the first moment's bias correction folded in
    float mInverseCorrection2 = 1.0f;        ///< this step's second-moment bias correction
};

}  // namespace gvr
