/// @file Adam.h
/// @brief Adam with one learning rate per parameter group.
#pragma once

#include "GaussianParameters.h"

#include <array>

namespace gvr {

struct AdamSettings {
    double beta1 = 0.9;
    double beta2 = 0.999;
    double epsilon = 1e-12;
};

class Adam {
public:
    Adam(std::size_t count, int channels, const AdamSettings& settings = {});

    /// One step: params -= rate[g] * mhat / (sqrt(vhat) + eps), per group g.
    void step(GaussianParameters& params, const GaussianParameters& gradient,
              const std::array<double, kGroupCount>& rates);

    /// Drops the moments of removed Gaussians, in step with params.keepOnly().
    void keepOnly(const std::vector<bool>& keep);
    /// Adds zeroed moments for Gaussians appended to the parameters.
    void grow(std::size_t count);

private:
    AdamSettings mSettings;
    GaussianParameters mFirst, mSecond;
    std::size_t mSteps = 0;
};

}  // namespace gvr
