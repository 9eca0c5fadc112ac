/// @file QualityMetrics.h
/// @brief MSE, PSNR, SSIM and MS-SSIM between two volumes or images of the same size.
///
/// SSIM follows Wang et al. (2004) as scikit-image computes it with
/// gaussian_weights=True, use_sample_covariance=False: Gaussian-weighted local
/// statistics (sigma 1.5, truncated at radius 5, an 11-tap window) along every
/// axis of at least 11 samples, averaged over the samples whose window lies
/// inside the volume. Axes shorter than the window are not smoothed (a window of
/// one sample along them), so an image is a volume one sample deep.
///
/// MS-SSIM follows Wang, Simoncelli and Bovik (2003): contrast-structure terms at
/// the first M-1 scales and the full SSIM at scale M, combined with the weights
/// 0.0448, 0.2856, 0.3001, 0.2363, 0.1333; each scale halves the smoothed axes by
/// averaging pairs (an odd last sample is dropped). Fallback: when the volume is
/// too small for 5 scales (a smoothed axis would fall below 11 samples), M is the
/// largest count that fits and the first M weights are rescaled to sum to 1.
/// Negative terms are clamped to 0 before the powers.
///
/// Multi-channel inputs are compared channel by channel and the results averaged.
#pragma once

#include "pipeline/FloatVolume.h"

namespace gvr {

struct SsimSettings {
    double dataRange = 1.0;  ///< L in C1 = (K1 L)^2 and C2 = (K2 L)^2; must be > 0
    double sigma = 1.5;      ///< of the Gaussian window, in samples
    int radius = 5;          ///< window half-width in samples: 11 taps
    double k1 = 0.01, k2 = 0.03;
};

/// Mean squared error over all samples and channels, or over the voxels whose
/// @a mask flag is set (mask empty: all voxels). Zero when no voxel counts.
double meanSquaredError(const FloatVolume& a, const FloatVolume& b, const std::vector<std::uint8_t>& mask = {});

/// The largest |a - b| over every channel of the voxels in @a mask (all when empty),
/// in double: the figure an error bound promises.
double maxAbsoluteError(const FloatVolume& a, const FloatVolume& b, const std::vector<std::uint8_t>& mask = {});

double ssim(const FloatVolume& a, const FloatVolume& b, const SsimSettings& settings);

/// Two renderings (premultiplied RGBA, 4 channels) compared as they are seen: RGB
/// composited over black and over white, on the pixels that either image covers
/// (alpha > 0). Alpha and the transparent background that both share would
/// otherwise raise every figure.
struct RenderingError {
    double overBlack = 0, overWhite = 0;  ///< mean squared error per RGB channel; 0 with no pixel covered
    std::size_t coveredPixels = 0;
};
/// @throw std::invalid_argument unless both have 4 channels and the same shape.
RenderingError renderingError(const FloatVolume& reference, const FloatVolume& test);

/// Where two renderings differ as they are seen: per pixel and RGB channel, the
/// root mean square of the differences over black and over white (what
/// renderingError averages), times @a gain, opaque. Pixels that neither image
/// covers are black.
/// @throw std::invalid_argument as renderingError.
FloatVolume renderingDifference(const FloatVolume& reference, const FloatVolume& test, float gain);

struct MsSsim {
    double value = 0.0;
    int scales = 0;  ///< M, 5 unless the fallback applied
};

MsSsim msSsim(const FloatVolume& a, const FloatVolume& b, const SsimSettings& settings);

/// The number of MS-SSIM scales a volume of @a dims allows (1 to 5).
int msSsimScales(const openvdb::Coord& dims, const SsimSettings& settings);

}  // namespace gvr
