/// @file Fitter.h
/// @brief The fit: Gaussians that approximate a volume, by Adam on an importance-
/// sampled Monte Carlo voxel loss plus a curriculum of random-slice losses.
#pragma once

#include "pipeline/AmplitudeSolver.h"
#include "pipeline/FitSettings.h"
#include "pipeline/GaussianParameters.h"
#include "pipeline/VolumeTarget.h"

#include <functional>
#include <optional>
#include <string>

namespace gvr {

/// What the fit reports after each iteration.
struct FitProgress {
    std::size_t iteration = 0;   ///< iterations finished
    double seconds = 0.0;        ///< since the fit started, initialisation included
    double fraction = 0.0;       ///< of the budget spent, in [0, 1]
    double loss = 0.0;           ///< lambda_v * voxel term + lambda_s * slice term
    double sliceWeight = 0.0;    ///< lambda_s at this iteration
    double gradientShare = 0.0;  ///< of the Gaussians, the share that got a gradient
    bool heldOutEvaluated = false;
    double heldOutPsnr = 0.0;  ///< dB, on the fixed held-out voxels; peak = target.peak()
    std::size_t gaussians = 0;
    std::size_t skippedSteps = 0;  ///< steps dropped for a non-finite gradient or result
    /// Set while the fit sets up, before an iteration: how far the seeding is, in [0, 1].
    std::optional<double> setUp;
};

using FitObserver = std::function<void(const FitProgress&)>;

struct FitReport {
    std::size_t iterations = 0;
    double seconds = 0.0;
    std::size_t skippedSteps = 0;
    std::size_t pruned = 0;
    std::size_t respawned = 0;
    std::size_t added = 0;           ///< Gaussians added where the byte budget had room (FitSettings::roomInBudget)
    double voxelSamples = 0.0;       ///< voxels the voxel loss evaluated, over all iterations
    double setupSeconds = 0.0;       ///< before the first iteration: held-out voxels, blocks, seeds
    double adamSeconds = 0.0;        ///< seconds of the iterations, before the amplitude solve
    double meanGradientShare = 0.0;  ///< the gradient share (FitProgress) averaged over iterations
    /// Gaussians asked for, when the time budget could train fewer and the fit
    /// kept fewer (FitSettings::minSamplesPerGaussian); else 0.
    std::size_t requestedGaussians = 0;
    AmplitudeSolveReport amplitudeSolve;
    std::string amplitudeSolveSkipped;  ///< why the solve did not run, in words; empty if it ran
};

/// Fits settings.gaussians Gaussians to @a target (index space). Same settings,
/// seed and iteration budget give the same result whatever the thread count; a
/// time budget stops wherever the clock says. An empty volume (no active voxel)
/// gives no Gaussians.
/// @throw InputError when settings.validate() fails.
GaussianParameters fitGaussians(const VolumeTarget& target, const FitSettings& settings,
                                const FitObserver& observer = {}, FitReport* report = nullptr);

/// PSNR in dB of a mean squared error against a peak; +inf for a zero error.
double psnrFromMse(double mse, double peak);

}  // namespace gvr
