/// @file GaussianKernel.h
/// @brief One Gaussian: activation, truncated evaluation, and its adjoint.
///
/// A Gaussian contributes amplitude * exp(-q/2) at x, where q = (x-mu)^T Sigma^-1 (x-mu),
/// Sigma = R S^2 R^T, amplitude = opacity * colour. The field is truncated: where
/// q > cutoff^2 the contribution is exactly zero. Fit, export and render all use
/// the cutoff stored with the model (kDefaultCutoffSigmas unless set otherwise).
#pragma once

#include "pipeline/GaussianParameters.h"

#include <cmath>

namespace gvr {

/// Truncation radius in standard deviations; exp(-3^2/2) = 1.1 % of the peak is cut.
constexpr float kDefaultCutoffSigmas = 3.0f;

/// Log-scale limits, in voxels: 1e-3 to about 8000 voxels, so that 1/sigma^2 and
/// sigma^2 both stay well inside float range.
constexpr float kMinLogScale = -6.9f;
constexpr float kMaxLogScale = 9.0f;

/// A Gaussian after activation, ready to evaluate. Index space throughout. The fit
/// keeps one for every Gaussian, so it holds only what evaluation and the rotation
/// adjoint read; the backward pass derives the rest (the unit quaternion, opacity
/// and colour) from the parameters, once per Gaussian and step.
struct ActiveGaussian {
    float mean[3];
    float rotation[9];           ///< row-major R; column a is the Gaussian's axis a
    float invVariance[3];        ///< 1 / sigma_a^2, sigma_a the standard deviation along axis a, voxels
    float inverseCovariance[6];  ///< R S^-2 R^T in world axes: xx, yy, zz, xy, xz, yz
    float amplitude[3];          ///< opacity * colour
};

float sigmoid(float x);

/// A raw quaternion made unit, with the norm its adjoint divides by.
struct UnitQuaternion {
    float q[4];  ///< (w, x, y, z)
    float norm;  ///< of the raw quaternion; 0 when it vanished, and q is then the identity
};

UnitQuaternion unitQuaternion(const float raw[4]);

/// Unit quaternion (w, x, y, z) to a row-major rotation matrix.
void rotationFromQuaternion(const float q[4], float r[9]);

ActiveGaussian activate(const GaussianParameters& params, std::size_t index);

/// The largest |opacity * colour_c| over the channels: how much Gaussian @a index
/// can add to the field anywhere.
float peakAmplitude(const GaussianParameters& params, std::size_t index);

/// Axis-aligned box around the truncated ellipsoid (q <= cutoff^2).
void truncatedBounds(const ActiveGaussian& g, float cutoffSigmas, float lower[3], float upper[3]);

/// Squared Mahalanobis distance of x, and u = R^T (x - mean), the local coordinates.
inline float mahalanobis2(const ActiveGaussian& g, const float x[3], float u[3]) {
    const float d[3] = {x[0] - g.mean[0], x[1] - g.mean[1], x[2] - g.mean[2]};
    float q = 0.0f;
    for (int a = 0; a < 3; ++a) {
        u[a] = g.rotation[a] * d[0] + g.rotation[3 + a] * d[1] + g.rotation[6 + a] * d[2];
        q += u[a] * u[a] * g.invVariance[a];
    }
    return q;
}

/// Adds this Gaussian's contribution at x to value[0..channels).
inline void accumulateValue(const ActiveGaussian& g, const float x[3], float cutoff2, int channels, float* value) {
    float u[3];
    const float q = mahalanobis2(g, x, u);
    if (q > cutoff2) return;
    const float e = std::exp(-0.5f * q);
    for (int c = 0; c < channels; ++c) value[c] += g.amplitude[c] * e;
}

/// Adds dL/d(parameters of Gaussian @a index) to @a gradient at @a index, given
/// dL/df at x (@a upstream, one per channel); @a g is that Gaussian of @a params,
/// activated. Zero outside the cutoff, like the value.
void accumulateGradient(const GaussianParameters& params, const ActiveGaussian& g, std::size_t index, const float x[3],
                        float cutoff2, const float* upstream, GaussianParameters& gradient);

/// One Gaussian's gradient summed over many points, gathered in world axes about
/// its mean, so that a block's moments add without a rotation and the adjoints of
/// the rotation and the quaternion run once per Gaussian, not per point or block.
/// With t = -e/2 sum_c upstream_c amplitude_c = dL/dq at a point, d = x - mean:
struct GradientSums {
    float upstreamE[3] = {0, 0, 0};     ///< sum of upstream_c e, per channel
    float td[3] = {0, 0, 0};            ///< sum of t d_a
    float tdd[6] = {0, 0, 0, 0, 0, 0};  ///< sum of t d_a d_b: xx, yy, zz, xy, xz, yz

    /// Adds one point inside the cutoff: d = x - mean, e = exp(-q/2).
    void add(const ActiveGaussian& g, int channels, const float d[3], float e, const float* upstream) {
        float upstreamDotAmplitude = 0.0f;
        for (int c = 0; c < channels; ++c) {
            upstreamE[c] += upstream[c] * e;
            upstreamDotAmplitude += upstream[c] * g.amplitude[c];
        }
        const float t = -0.5f * upstreamDotAmplitude * e;
        for (int a = 0; a < 3; ++a) td[a] += t * d[a];
        tdd[0] += t * d[0] * d[0];
        tdd[1] += t * d[1] * d[1];
        tdd[2] += t * d[2] * d[2];
        tdd[3] += t * d[0] * d[1];
        tdd[4] += t * d[0] * d[2];
        tdd[5] += t * d[1] * d[2];
    }

    GradientSums& operator+=(const GradientSums& other) {
        for (int k = 0; k < 3; ++k) upstreamE[k] += other.upstreamE[k];
        for (int k = 0; k < 3; ++k) td[k] += other.td[k];
        for (int k = 0; k < 6; ++k) tdd[k] += other.tdd[k];
        return *this;
    }
};

/// Adds to @a gradient, at @a gradientIndex, what the points gathered in @a sums
/// give Gaussian @a index of @a params (@a g, activated): the same as calling
/// accumulateGradient() at each of them, up to rounding.
void accumulateGradient(const GaussianParameters& params, const ActiveGaussian& g, std::size_t index,
                        const GradientSums& sums, GaussianParameters& gradient, std::size_t gradientIndex);

/// Adjoint of rotationFromQuaternion followed by normalisation: dL/dR (row-major)
/// to dL/d(raw quaternion).
void quaternionAdjoint(const UnitQuaternion& unit, const float dR[9], float dQuat[4]);

}  // namespace gvr
