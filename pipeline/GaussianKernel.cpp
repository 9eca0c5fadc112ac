#include "pipeline/GaussianKernel.h"

#include <algorithm>
#include <cmath>

namespace gvr {

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

void rotationFromQuaternion(const float q[4], float r[9]) {
    const float w = q[0], x = q[1], y = q[2], z = q[3];
    r[0] = 1 - 2 * (y * y + z * z);
    r[1] = 2 * (x * y - w * z);
    r[2] = 2 * (x * z + w * y);
    r[3] = 2 * (x * y + w * z);
    r[4] = 1 - 2 * (x * x + z * z);
    r[5] = 2 * (y * z - w * x);
    r[6] = 2 * (x * z - w * y);
    r[7] = 2 * (y * z + w * x);
    r[8] = 1 - 2 * (x * x + y * y);
}

UnitQuaternion unitQuaternion(const float raw[4]) {
    UnitQuaternion unit{};
    unit.norm = std::sqrt(raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2] + raw[3] * raw[3]);
    if (unit.norm > 1e-12f) {
        for (int k = 0; k < 4; ++k) unit.q[k] = raw[k] / unit.norm;
    } else {  // a vanished quaternion means no rotation; its gradient is dropped
        unit.q[0] = 1.0f;
        unit.norm = 0.0f;
    }
    return unit;
}

float peakAmplitude(const GaussianParameters& params, std::size_t index) {
    const float opacity = sigmoid(*params.at(kOpacityLogits, index));
    float peak = 0.0f;
    for (int c = 0; c < params.channels; ++c) peak = std::max(peak, std::abs(opacity * params.at(kColours, index)[c]));
    return peak;
}

namespace {

/// Sigma^-1 = R S^-2 R^T, summed in double: its entries cancel for thin Gaussians.
void setInverseCovariance(ActiveGaussian& g) {
    constexpr int kRows[6] = {0, 1, 2, 0, 0, 1}, kColumns[6] = {0, 1, 2, 1, 2, 2};
    for (int k = 0; k < 6; ++k) {
        double sum = 0.0;
        for (int c = 0; c < 3; ++c) {
            sum += double(g.invVariance[c]) * g.rotation[3 * kRows[k] + c] * g.rotation[3 * kColumns[k] + c];
        }
        g.inverseCovariance[k] = float(sum);
    }
}

}  // namespace

ActiveGaussian activate(const GaussianParameters& params, std::size_t index) {
    ActiveGaussian g{};
    std::copy_n(params.at(kMeans, index), 3, g.mean);
    rotationFromQuaternion(unitQuaternion(params.at(kRotations, index)).q, g.rotation);
    const float* logScale = params.at(kLogScales, index);
    for (int a = 0; a < 3; ++a) {
        const float scale = std::exp(std::clamp(logScale[a], kMinLogScale, kMaxLogScale));
        g.invVariance[a] = 1.0f / (scale * scale);
    }
    setInverseCovariance(g);
    const float opacity = sigmoid(*params.at(kOpacityLogits, index));
    const float* colour = params.at(kColours, index);
    for (int c = 0; c < params.channels; ++c) g.amplitude[c] = opacity * colour[c];
    return g;
}

void truncatedBounds(const ActiveGaussian& g, float cutoffSigmas, float lower[3], float upper[3]) {
    // Half-extent along world axis a is cutoff * sqrt(Sigma_aa), Sigma = R S^2 R^T.
    for (int a = 0; a < 3; ++a) {
        float variance = 0.0f;
        for (int b = 0; b < 3; ++b) {
            const float r = g.rotation[3 * a + b];
            variance += r * r / g.invVariance[b];
        }
        const float half = cutoffSigmas * std::sqrt(variance);
        lower[a] = g.mean[a] - half;
        upper[a] = g.mean[a] + half;
    }
}

void quaternionAdjoint(const UnitQuaternion& unit, const float dR[9], float dQuat[4]) {
    if (unit.norm == 0.0f) {
        std::fill_n(dQuat, 4, 0.0f);
        return;
    }
    const float w = unit.q[0], x = unit.q[1], y = unit.q[2], z = unit.q[3];
    // dL/dq_hat: each term is dR_ij/dq times dL/dR_ij, from rotationFromQuaternion.
    const float dHat[4] = {
        2 * (-z * dR[1] + y * dR[2] + z * dR[3] - x * dR[5] - y * dR[6] + x * dR[7]),
        2 * (y * dR[1] + z * dR[2] + y * dR[3] - 2 * x * dR[4] - w * dR[5] + z * dR[6] + w * dR[7] - 2 * x * dR[8]),
        2 * (-2 * y * dR[0] + x * dR[1] + w * dR[2] + x * dR[3] + z * dR[5] - w * dR[6] + z * dR[7] - 2 * y * dR[8]),
        2 * (-2 * z * dR[0] - w * dR[1] + x * dR[2] + w * dR[3] - 2 * z * dR[4] + y * dR[5] + x * dR[6] + y * dR[7])};
    // q_hat = q / |q|:  dL/dq = (dL/dq_hat - q_hat (q_hat . dL/dq_hat)) / |q|
    const float along = w * dHat[0] + x * dHat[1] + y * dHat[2] + z * dHat[3];
    for (int k = 0; k < 4; ++k) dQuat[k] = (dHat[k] - unit.q[k] * along) / unit.norm;
}

void accumulateGradient(const GaussianParameters& params, const ActiveGaussian& g, std::size_t index, const float x[3],
                        float cutoff2, const float* upstream, GaussianParameters& gradient) {
    float u[3];
    const float q = mahalanobis2(g, x, u);
    if (q > cutoff2) return;
    const float d[3] = {x[0] - g.mean[0], x[1] - g.mean[1], x[2] - g.mean[2]};
    GradientSums sums;
    sums.add(g, gradient.channels, d, std::exp(-0.5f * q), upstream);
    accumulateGradient(params, g, index, sums, gradient, index);
}

void accumulateGradient(const GaussianParameters& params, const ActiveGaussian& g, std::size_t index,
                        const GradientSums& sums, GaussianParameters& gradient, std::size_t gradientIndex) {
    const int channels = gradient.channels;
    const float opacity = sigmoid(*params.at(kOpacityLogits, index));
    const float* colour = params.at(kColours, index);
    float* dColour = gradient.at(kColours, gradientIndex);
    float upstreamDotColour = 0.0f;
    for (int c = 0; c < channels; ++c) {
        dColour[c] += opacity * sums.upstreamE[c];
        upstreamDotColour += colour[c] * sums.upstreamE[c];
    }
    *gradient.at(kOpacityLogits, gradientIndex) += upstreamDotColour * opacity * (1.0f - opacity);

    // In the Gaussian's frame u = R^T d, and per point dL/du_a = 2 t u_a / sigma_a^2,
    // so dL/dmean = -R (2 S^-2 R^T sum t d) and dL/dR = 2 T R S^-2 with T = sum t d d^T;
    // dL/dlog sigma_a = -2 (R^T T R)_aa / sigma_a^2.
    const float T[3][3] = {{sums.tdd[0], sums.tdd[3], sums.tdd[4]},
                           {sums.tdd[3], sums.tdd[1], sums.tdd[5]},
                           {sums.tdd[4], sums.tdd[5], sums.tdd[2]}};
    float TR[3][3] = {}, dU[3] = {0, 0, 0};
    for (int b = 0; b < 3; ++b) {
        for (int a = 0; a < 3; ++a) {
            for (int c = 0; c < 3; ++c) TR[b][a] += T[b][c] * g.rotation[3 * c + a];
            dU[a] += g.rotation[3 * b + a] * sums.td[b];
        }
    }
    float* dLogScale = gradient.at(kLogScales, gradientIndex);
    float dR[9];
    for (int a = 0; a < 3; ++a) {
        dU[a] *= 2.0f * g.invVariance[a];
        float uTu = 0.0f;
        for (int b = 0; b < 3; ++b) {
            dR[3 * b + a] = 2.0f * g.invVariance[a] * TR[b][a];
            uTu += g.rotation[3 * b + a] * TR[b][a];
        }
        dLogScale[a] += -2.0f * g.invVariance[a] * uTu;
    }
    float* dMean = gradient.at(kMeans, gradientIndex);
    for (int b = 0; b < 3; ++b) {
        dMean[b] -= g.rotation[3 * b] * dU[0] + g.rotation[3 * b + 1] * dU[1] + g.rotation[3 * b + 2] * dU[2];
    }
    float dQuat[4];
    quaternionAdjoint(unitQuaternion(params.at(kRotations, index)), dR, dQuat);
    float* dRotation = gradient.at(kRotations, gradientIndex);
    for (int k = 0; k < 4; ++k) dRotation[k] += dQuat[k];
}

}  // namespace gvr
