#include "pipeline/QualityMetrics.h"

#include "pipeline/BoxAverage.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace gvr {

namespace {

constexpr double kMsSsimWeights[5] = {0.0448, 0.2856, 0.3001, 0.2363, 0.1333};

void requireSameShape(const FloatVolume& a, const FloatVolume& b) {
    if (a.dims != b.dims || a.channels != b.channels) {
        throw std::invalid_argument("quality metrics need volumes of the same dimensions and channels");
    }
}

/// One channel of a volume, read in place: the samples of a FloatVolume (every
/// `stride`-th float) or of a coarser scale that owns its samples. Statistics are
/// summed in double, since local variances are differences of large squares (HU
/// squared reaches 1e7).
struct Channel {
    openvdb::Coord dims;
    const float* samples = nullptr;
    int stride = 1;
    std::vector<float> owned;  ///< a coarser scale's samples; `samples` points here

    double at(int i, int j, int k) const { return samples[((std::size_t(k) * dims.y() + j) * dims.x() + i) * stride]; }
};

Channel channelOf(const FloatVolume& volume, int channel) {
    return {volume.dims, volume.values.data() + channel, volume.channels, {}};
}

using Axes = std::array<bool, 3>;

/// The axes long enough for the window; only these are smoothed and halved.
Axes smoothedAxes(const openvdb::Coord& dims, const SsimSettings& settings) {
    return {dims.x() > 2 * settings.radius, dims.y() > 2 * settings.radius, dims.z() > 2 * settings.radius};
}

std::vector<double> gaussianWindow(const SsimSettings& settings) {
    std::vector<double> window(2 * settings.radius + 1);
    for (int d = -settings.radius; d <= settings.radius; ++d) {
        window[d + settings.radius] = std::exp(-0.5 * d * d / (settings.sigma * settings.sigma));
    }
    const double sum = std::accumulate(window.begin(), window.end(), 0.0);
    for (double& w : window) w /= sum;
    return window;
}

/// The five local statistics E[a], E[b], E[a^2], E[b^2], E[ab] on one plane.
using Stats = std::array<std::vector<double>, 5>;

struct SsimTerms {
    double ssim = 0.0;  ///< mean SSIM over the valid samples
    double cs = 0.0;    ///< mean contrast-structure term
};

/// Computes the local statistics plane by plane, filtering each input plane along
/// x and y once and keeping the last window's worth of planes for the z filter,
/// so memory stays at a few planes whatever the depth.
class SsimAccumulator {
public:
    SsimAccumulator(const Channel& a, const Channel& b, const SsimSettings& settings, const Axes& smoothed)
        : mA(a), mB(b), mDims(a.dims) {
        const std::vector<double> gaussian = gaussianWindow(settings);
        for (int axis = 0; axis < 3; ++axis) {
            mWindow[axis] = smoothed[axis] ? gaussian : std::vector<double>{1.0};
            mOut[axis] = mDims[axis] - int(mWindow[axis].size()) + 1;
        }
        mC1 = std::pow(settings.k1 * settings.dataRange, 2);
        mC2 = std::pow(settings.k2 * settings.dataRange, 2);
        mRing.resize(mWindow[2].size());
    }

    SsimTerms run() {
        const int taps = int(mWindow[2].size());
        double ssimSum = 0.0, csSum = 0.0;
        for (int k = 0; k < mDims.z(); ++k) {
            filterPlane(k, mRing[k % taps]);
            if (k + 1 < taps) continue;
            const auto [ssim, cs] = combinePlanes(k + 1 - taps);
            ssimSum += ssim;
            csSum += cs;
        }
        const double samples = double(mOut[0]) * mOut[1] * mOut[2];
        return {ssimSum / samples, csSum / samples};
    }

private:
    /// Statistics of input plane @a k, filtered along x then y, valid region only.
    void filterPlane(int k, Stats& out) const {
        const int ox = mOut[0], oy = mOut[1];
        Stats alongX;
        for (auto& s : alongX) s.assign(std::size_t(mDims.y()) * ox, 0.0);
        tbb::parallel_for(0, mDims.y(), [&](int j) {
            for (int i = 0; i < ox; ++i) {
                double sums[5] = {0, 0, 0, 0, 0};
                for (std::size_t t = 0; t < mWindow[0].size(); ++t) {
                    const double a = mA.at(i + int(t), j, k), b = mB.at(i + int(t), j, k), w = mWindow[0][t];
                    sums[0] += w * a;
                    sums[1] += w * b;
                    sums[2] += w * a * a;
                    sums[3] += w * b * b;
                    sums[4] += w * a * b;
                }
                for (int s = 0; s < 5; ++s) alongX[s][std::size_t(j) * ox + i] = sums[s];
            }
        });
        for (auto& s : out) s.assign(std::size_t(oy) * ox, 0.0);
        tbb::parallel_for(0, oy, [&](int j) {
            for (std::size_t t = 0; t < mWindow[1].size(); ++t) {
                const double w = mWindow[1][t];
                for (int s = 0; s < 5; ++s) {
                    const double* in = alongX[s].data() + (std::size_t(j) + t) * ox;
                    double* o = out[s].data() + std::size_t(j) * ox;
                    for (int i = 0; i < ox; ++i) o[i] += w * in[i];
                }
            }
        });
    }

    /// Sums of SSIM and cs over output plane @a z, whose window starts at plane z.
    std::pair<double, double> combinePlanes(int z) const {
        const int ox = mOut[0], oy = mOut[1], taps = int(mWindow[2].size());
        std::vector<double> rowSsim(oy, 0.0), rowCs(oy, 0.0);
        tbb::parallel_for(0, oy, [&](int j) {
            for (int i = 0; i < ox; ++i) {
                const std::size_t n = std::size_t(j) * ox + i;
                double m[5] = {0, 0, 0, 0, 0};
                for (int t = 0; t < taps; ++t) {
                    const Stats& plane = mRing[(z + t) % taps];
                    for (int s = 0; s < 5; ++s) m[s] += mWindow[2][t] * plane[s][n];
                }
                const double varA = m[2] - m[0] * m[0], varB = m[3] - m[1] * m[1], cov = m[4] - m[0] * m[1];
                const double cs = (2.0 * cov + mC2) / (varA + varB + mC2);
                rowCs[j] += cs;
                rowSsim[j] += cs * (2.0 * m[0] * m[1] + mC1) / (m[0] * m[0] + m[1] * m[1] + mC1);
            }
        });
        return {std::accumulate(rowSsim.begin(), rowSsim.end(), 0.0), std::accumulate(rowCs.begin(), rowCs.end(), 0.0)};
    }

    const Channel& mA;
    const Channel& mB;
    openvdb::Coord mDims;
    std::array<std::vector<double>, 3> mWindow;
    std::array<int, 3> mOut{};
    double mC1 = 0.0, mC2 = 0.0;
    std::vector<Stats> mRing;
};

/// Halves the smoothed axes by averaging pairs, dropping an odd last sample.
/// Returned through @a out, whose samples must not move once they are pointed at.
void halve(const Channel& in, const Axes& smoothed, Channel& out) {
    openvdb::Coord dims = in.dims;
    for (int axis = 0; axis < 3; ++axis) {
        if (smoothed[axis]) dims[axis] /= 2;
    }
    std::vector<float> samples(std::size_t(dims.x()) * dims.y() * dims.z(), 0.0f);
    const openvdb::Coord factor(smoothed[0] ? 2 : 1, smoothed[1] ? 2 : 1, smoothed[2] ? 2 : 1);
    forEachBoxAverage(
        dims, factor, in.dims, 1, [&](int x, int y, int z, double* sums) { sums[0] += in.at(x, y, z); },
        [&](int i, int j, int k, const double* means) {
            samples[(std::size_t(k) * dims.y() + j) * dims.x() + i] = float(means[0]);
        });
    out.dims = dims;
    out.owned = std::move(samples);
    out.samples = out.owned.data();
    out.stride = 1;
}

}  // namespace

double meanSquaredError(const FloatVolume& a, const FloatVolume& b, const std::vector<std::uint8_t>& mask) {
    requireSameShape(a, b);
    const std::size_t perPlane = std::size_t(a.dims.x()) * a.dims.y();
    std::vector<double> planeSums(a.dims.z(), 0.0);
    std::vector<std::size_t> planeCounts(a.dims.z(), 0);
    tbb::parallel_for(0, a.dims.z(), [&](int k) {
        for (std::size_t n = perPlane * k; n < perPlane * (k + 1); ++n) {
            if (!mask.empty() && !mask[n]) continue;
            for (int c = 0; c < a.channels; ++c) {
                const double d = double(a.values[n * a.channels + c]) - b.values[n * a.channels + c];
                planeSums[k] += d * d;
            }
            ++planeCounts[k];
        }
    });
    const double sum = std::accumulate(planeSums.begin(), planeSums.end(), 0.0);
    const std::size_t count = std::accumulate(planeCounts.begin(), planeCounts.end(), std::size_t(0));
    return count > 0 ? sum / (double(count) * a.channels) : 0.0;
}

double maxAbsoluteError(const FloatVolume& a, const FloatVolume& b, const std::vector<std::uint8_t>& mask) {
    requireSameShape(a, b);
    double worst = 0.0;
    for (std::size_t n = 0; n < a.voxelCount(); ++n) {
        if (!mask.empty() && !mask[n]) continue;
        for (int c = 0; c < a.channels; ++c) {
            worst =
                std::max(worst, std::abs(double(a.values[n * a.channels + c]) - double(b.values[n * a.channels + c])));
        }
    }
    return worst;
}

namespace {

/// Whether either rendering covers pixel @a n (alpha > 0).
bool covered(const FloatVolume& reference, const FloatVolume& test, std::size_t n) {
    return reference.values[4 * n + 3] > 0.0f || test.values[4 * n + 3] > 0.0f;
}

/// Pixel @a n of two renderings, channel @a c, composited over black and over white:
/// the two differences.
std::pair<double, double> seenDifferences(const FloatVolume& reference, const FloatVolume& test, std::size_t n, int c) {
    const float* a = reference.values.data() + 4 * n;
    const float* b = test.values.data() + 4 * n;
    const double overBlack = double(a[c]) - b[c];                // premultiplied colour over black is itself
    const double overWhite = overBlack - (double(a[3]) - b[3]);  // plus (1 - alpha) of white
    return {overBlack, overWhite};
}

void requireRenderings(const FloatVolume& reference, const FloatVolume& test, const char* caller) {
    requireSameShape(reference, test);
    if (reference.channels != 4) throw std::invalid_argument(std::string(caller) + ": images must be RGBA");
}

}  // namespace

RenderingError renderingError(const FloatVolume& reference, const FloatVolume& test) {
    requireRenderings(reference, test, "renderingError");
    RenderingError error;
    double black = 0.0, white = 0.0;
    for (std::size_t n = 0; n < reference.voxelCount(); ++n) {
        if (!covered(reference, test, n)) continue;
        ++error.coveredPixels;
        for (int c = 0; c < 3; ++c) {
            const auto [overBlack, overWhite] = seenDifferences(reference, test, n, c);
            black += overBlack * overBlack;
            white += overWhite * overWhite;
        }
    }
    if (error.coveredPixels > 0) {
        error.overBlack = black / (3.0 * error.coveredPixels);
        error.overWhite = white / (3.0 * error.coveredPixels);
    }
    return error;
}

FloatVolume renderingDifference(const FloatVolume& reference, const FloatVolume& test, float gain) {
    requireRenderings(reference, test, "renderingDifference");
    FloatVolume difference(reference.dims, 4);
    for (std::size_t n = 0; n < reference.voxelCount(); ++n) {
        float* out = difference.values.data() + 4 * n;
        out[3] = 1.0f;
        if (!covered(reference, test, n)) continue;
        for (int c = 0; c < 3; ++c) {
            const auto [overBlack, overWhite] = seenDifferences(reference, test, n, c);
            out[c] = gain * float(std::sqrt(0.5 * (overBlack * overBlack + overWhite * overWhite)));
        }
    }
    return difference;
}

double ssim(const FloatVolume& a, const FloatVolume& b, const SsimSettings& settings) {
    requireSameShape(a, b);
    const Axes smoothed = smoothedAxes(a.dims, settings);
    double sum = 0.0;
    for (int c = 0; c < a.channels; ++c) {
        sum += SsimAccumulator(channelOf(a, c), channelOf(b, c), settings, smoothed).run().ssim;
    }
    return sum / a.channels;
}

int msSsimScales(const openvdb::Coord& dims, const SsimSettings& settings) {
    const Axes smoothed = smoothedAxes(dims, settings);
    if (!smoothed[0] && !smoothed[1] && !smoothed[2]) return 1;
    int scales = 1;
    while (scales < 5) {
        bool fits = true;
        for (int axis = 0; axis < 3; ++axis) {
            if (smoothed[axis] && (dims[axis] >> scales) <= 2 * settings.radius) fits = false;
        }
        if (!fits) break;
        ++scales;
    }
    return scales;
}

MsSsim msSsim(const FloatVolume& a, const FloatVolume& b, const SsimSettings& settings) {
    requireSameShape(a, b);
    const Axes smoothed = smoothedAxes(a.dims, settings);
    MsSsim result;
    result.scales = msSsimScales(a.dims, settings);
    const double weightSum = std::accumulate(kMsSsimWeights, kMsSsimWeights + result.scales, 0.0);
    for (int c = 0; c < a.channels; ++c) {
        Channel x = channelOf(a, c), y = channelOf(b, c);
        double product = 1.0;
        for (int scale = 0; scale < result.scales; ++scale) {
            const SsimTerms terms = SsimAccumulator(x, y, settings, smoothed).run();
            const bool last = scale + 1 == result.scales;
            const double term = std::max(0.0, last ? terms.ssim : terms.cs);
            product *= std::pow(term, kMsSsimWeights[scale] / weightSum);
            if (!last) {
                Channel coarserX, coarserY;
                halve(x, smoothed, coarserX);
                halve(y, smoothed, coarserY);
                x = std::move(coarserX);
                y = std::move(coarserY);
            }
        }
        result.value += product / a.channels;
    }
    return result;
}

}  // namespace gvr
