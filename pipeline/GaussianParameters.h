/// @file GaussianParameters.h
/// @brief The Gaussians as the optimiser sees them: named arrays in unconstrained form.
///
/// Like gsplat's parameter dictionary, every attribute is stored before its
/// activation (log-scale, raw quaternion, opacity logit), so any real value is a
/// valid Gaussian. Gradients and Adam moments use the same layout, so one
/// keepOnly() compacts all of them together.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gvr {

enum ParameterGroup { kMeans, kRotations, kLogScales, kOpacityLogits, kColours, kGroupCount };

/// Floats per Gaussian in @a group: 3, 4 (w, x, y, z), 3, 1 and @a channels.
int groupWidth(ParameterGroup group, int channels);

/// Human name of a group, for logs and errors ("means", "rotations", ...).
const char* groupName(ParameterGroup group);

struct GaussianParameters {
    int channels = 1;  ///< 1 grey, 3 RGB
    /// values[g] holds count() * groupWidth(g) floats, Gaussian after Gaussian.
    /// Means are in index space (voxel units); log-scales are natural logs of the
    /// standard deviations along the rotated axes, also in voxels; colours are in
    /// normalised units (0 = background, 1 = top of the data range).
    std::array<std::vector<float>, kGroupCount> values;

    GaussianParameters() = default;
    GaussianParameters(std::size_t count, int channels);  ///< all zeros

    std::size_t count() const { return values[kMeans].size() / 3; }
    int width(ParameterGroup group) const { return groupWidth(group, channels); }

    float* at(ParameterGroup group, std::size_t index) {
        return values[group].data() + index * std::size_t(width(group));
    }
    const float* at(ParameterGroup group, std::size_t index) const {
        return values[group].data() + index * std::size_t(width(group));
    }

    void setZero();
    /// Keeps the Gaussians whose flag is true, in order. @a keep has count() flags.
    void keepOnly(const std::vector<bool>& keep);
    /// Puts Gaussian order[k] at k, for every k; @a order is a permutation of 0..count()-1.
    void permute(const std::vector<std::uint32_t>& order);
    /// Adds @a other element-wise; both must have the same count and channels.
    void add(const GaussianParameters& other);
    /// Puts @a more's Gaussians after these; both must have the same channels.
    void append(const GaussianParameters& more);
    bool allFinite() const;
};

}  // namespace gvr
