/// @file AmplitudeSolver.h
/// @brief The best amplitudes for fixed geometry, by conjugate gradients.
///
/// With means, rotations and scales fixed, the field is linear in the amplitudes
/// (opacity x colour): f(x) = sum_i a_i g_i(x), g_i(x) = exp(-q_i(x)/2) inside the
/// cutoff. The amplitudes that minimise the dense voxel MSE solve the normal equations
/// G^T G a = G^T t. Conjugate gradients reach them in a few iterations, each one pass
/// over the volume in 8^3 blocks (one BVH query per block, the forward and adjoint
/// products together), where Adam's Monte Carlo steps only approach them.
#pragma once

#include "pipeline/GaussianParameters.h"
#include "pipeline/VolumeTarget.h"

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace gvr {

struct AmplitudeSolveSettings {
    std::size_t iterations = 10;  ///< conjugate-gradient iterations at most
    double seconds = 0.0;         ///< stop before an iteration that would overrun this (0: no limit)
    float cutoffSigmas = 3.0f;
    /// Voxels left out of the least squares (the fit's held-out voxels).
    std::vector<openvdb::Coord> excluded;
    /// Called after every pass over the volume (each takes about a dense measurement).
    std::function<void()> afterPass;
};

struct AmplitudeSolveReport {
    std::size_t iterations = 0;
    double mseBefore = 0.0, mseAfter = 0.0;  ///< dense, per channel, normalised units
    double seconds = 0.0;
};

/// Replaces the amplitudes of @a params by the least-squares ones over every voxel
/// of target.box() but the excluded ones (colours change, opacities stay). The result does not depend on
/// the thread count. If the solve does not lower the dense MSE (it always should),
/// the parameters are left as they were.
AmplitudeSolveReport solveAmplitudes(GaussianParameters& params, const VolumeTarget& target,
                                     const AmplitudeSolveSettings& settings);

}  // namespace gvr
