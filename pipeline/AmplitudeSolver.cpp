#include "pipeline/AmplitudeSolver.h"

#include "pipeline/BlockGrid.h"
#include "pipeline/GaussianField.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

/// Blocks are split into this many fixed runs, each summed on its own and then in
/// order, so that the result does not depend on the thread count.
constexpr std::size_t kChunks = 16;
/// Runs evaluated at once. Each holds a dense sum over every Gaussian until it is
/// added in, so all sixteen at once were the largest buffers of a whole fit.
constexpr std::size_t kChunksAtOnce = 4;
static_assert(kChunks % kChunksAtOnce == 0);

/// One Gaussian's kernel value at one voxel of a block.
struct Entry {
    std::uint16_t voxel;  // blockOffset() of the voxel
    std::uint32_t gaussian;
    float e;
};

/// The trainable voxels of the target's box, held-out ones left out.
BlockGrid trainingGrid(const VolumeTarget& target, std::vector<openvdb::Coord> excluded) {
    excluded.erase(std::remove_if(excluded.begin(), excluded.end(),
                                  [&](const openvdb::Coord& ijk) { return !target.box().isInside(ijk); }),
                   excluded.end());
    return BlockGrid(target.box(), excluded);
}

/// The products G v and G^T w over the target's box, one block at a time.
class DesignMatrix {
public:
    DesignMatrix(const GaussianField& field, const VolumeTarget& target, const std::vector<openvdb::Coord>& excluded)
        : mField(field), mTarget(target), mGrid(trainingGrid(target, excluded)) {}

    /// Returns G^T w with w = t - G v (@a residual) or w = G v, and in @a squared the
    /// sum over voxels and channels of w^2.
    std::vector<double> apply(const std::vector<double>& v, bool residual, double& squared) const {
        const std::size_t width = mField.gaussians().size() * std::size_t(mField.channels());
        const std::size_t blocks = mGrid.blockCount();
        std::vector<double> sum(width, 0.0);
        squared = 0.0;
        std::array<std::vector<double>, kChunksAtOnce> out;
        for (std::size_t first = 0; first < kChunks; first += kChunksAtOnce) {
            std::array<double, kChunksAtOnce> partial{};
            tbb::parallel_for(std::size_t(0), kChunksAtOnce, [&](std::size_t k) {
                const std::size_t c = first + k;
                out[k].assign(width, 0.0);
                std::vector<Entry> entries;
                std::vector<std::uint32_t> hits;
                for (std::size_t b = c * blocks / kChunks; b < (c + 1) * blocks / kChunks; ++b) {
                    partial[k] += applyBlock(std::uint32_t(b), v, residual, entries, hits, out[k]);
                }
            });
            for (std::size_t k = 0; k < kChunksAtOnce; ++k) {  // in chunk order, as if all ran at once
                for (std::size_t j = 0; j < width; ++j) sum[j] += out[k][j];
                squared += partial[k];
            }
        }
        return sum;
    }

    std::uint64_t valueCount() const { return mGrid.trainableVoxels() * std::uint64_t(mField.channels()); }

private:
    /// Kernel values of the Gaussians reaching the block's voxels @a box, in a fixed order.
    void blockEntries(const openvdb::CoordBBox& box, std::vector<Entry>& entries,
                      std::vector<std::uint32_t>& hits) const {
        const float lower[3] = {float(box.min().x()), float(box.min().y()), float(box.min().z())};
        const float upper[3] = {float(box.max().x()), float(box.max().y()), float(box.max().z())};
        mField.bvh().overlapping(lower, upper, hits);
        std::sort(hits.begin(), hits.end());
        entries.clear();
        for (std::uint32_t g : hits) {
            const ActiveGaussian& gaussian = mField.gaussians()[g];
            // Only the voxels inside the Gaussian's truncated bounds can be reached.
            const Box& reach = mField.bvh().boxes()[g];
            int from[3], to[3];
            for (int a = 0; a < 3; ++a) {
                from[a] = std::max(box.min()[a], int(std::ceil(reach.lower[a])));
                to[a] = std::min(box.max()[a], int(std::floor(reach.upper[a])));
            }
            for (int z = from[2]; z <= to[2]; ++z) {
                for (int y = from[1]; y <= to[1]; ++y) {
                    for (int x = from[0]; x <= to[0]; ++x) {
                        const float point[3] = {float(x), float(y), float(z)};
                        float u[3];
                        const float q = mahalanobis2(gaussian, point, u);
                        if (q > mField.cutoff2()) continue;
                        const int voxel = blockOffset(openvdb::Coord(x, y, z));
                        entries.push_back({std::uint16_t(voxel), g, std::exp(-0.5f * q)});
                    }
                }
            }
        }
    }

    double applyBlock(std::uint32_t block, const std::vector<double>& v, bool residual, std::vector<Entry>& entries,
                      std::vector<std::uint32_t>& hits, std::vector<double>& out) const {
        const openvdb::Coord origin = mGrid.origin(block);
        openvdb::CoordBBox box(origin, origin.offsetBy(kBlockDim - 1));
        box.intersect(mGrid.box());
        blockEntries(box, entries, hits);
        const int channels = mField.channels();
        std::array<double, 3 * kBlockVoxels> w{};
        for (const Entry& entry : entries) {
            for (int c = 0; c < channels; ++c)
                w[entry.voxel * channels + c] += entry.e * v[entry.gaussian * channels + c];
        }
        std::int32_t trainable[kBlockVoxels];
        mGrid.trainableMask(block, trainable);
        float expected[3 * kBlockVoxels];
        if (residual) mTarget.blockValues(origin, expected);
        // x fastest: the order the sum of squares has always been taken in.
        double squared = 0.0;
        for (int z = box.min().z(); z <= box.max().z(); ++z) {
            for (int y = box.min().y(); y <= box.max().y(); ++y) {
                for (int x = box.min().x(); x <= box.max().x(); ++x) {
                    const int k = blockOffset(openvdb::Coord(x, y, z));
                    for (int c = 0; c < channels; ++c) {
                        double& value = w[k * channels + c];
                        if (!trainable[k]) {
                            value = 0.0;
                        } else if (residual) {
                            value = expected[k * channels + c] - value;
                        }
                        squared += value * value;
                    }
                }
            }
        }
        for (const Entry& entry : entries) {
            for (int c = 0; c < channels; ++c)
                out[entry.gaussian * channels + c] += entry.e * w[entry.voxel * channels + c];
        }
        return squared;
    }

    const GaussianField& mField;
    const VolumeTarget& mTarget;
    BlockGrid mGrid;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) sum += a[k] * b[k];
    return sum;
}

std::vector<double> amplitudesOf(const GaussianParameters& params) {
    std::vector<double> a(params.count() * std::size_t(params.channels));
    for (std::size_t i = 0; i < params.count(); ++i) {
        const float opacity = sigmoid(*params.at(kOpacityLogits, i));
        for (int c = 0; c < params.channels; ++c)
            a[i * params.channels + c] = double(opacity) * params.at(kColours, i)[c];
    }
    return a;
}

void setAmplitudes(GaussianParameters& params, const std::vector<double>& a) {
    for (std::size_t i = 0; i < params.count(); ++i) {
        const double opacity = sigmoid(*params.at(kOpacityLogits, i));
        for (int c = 0; c < params.channels; ++c)
            params.at(kColours, i)[c] = float(a[i * params.channels + c] / opacity);
    }
}

}  // namespace

AmplitudeSolveReport solveAmplitudes(GaussianParameters& params, const VolumeTarget& target,
                                     const AmplitudeSolveSettings& settings) {
    const Clock::time_point start = Clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    AmplitudeSolveReport report;
    if (params.count() == 0 || target.box().empty()) return report;

    const GaussianField field(params, settings.cutoffSigmas);
    const DesignMatrix matrix(field, target, settings.excluded);
    const double values = double(matrix.valueCount());
    std::vector<double> a = amplitudesOf(params);
    double squared = 0.0;
    const auto passDone = [&] {
        if (settings.afterPass) settings.afterPass();
    };
    std::vector<double> r = matrix.apply(a, /*residual=*/true, squared);  // G^T (t - G a)
    passDone();
    report.mseBefore = squared / values;
    std::vector<double> p = r;
    double rr = dot(r, r);
    double passSeconds = elapsed();
    // An iteration is worth starting only if it and the closing pass both fit.
    const auto timeForAnIteration = [&] {
        return settings.seconds <= 0.0 || elapsed() + 2.0 * passSeconds <= settings.seconds;
    };
    if (!timeForAnIteration()) {  // the closing pass would only confirm the amplitudes as they are
        report.mseAfter = report.mseBefore;
        report.seconds = elapsed();
        return report;
    }
    while (report.iterations < settings.iterations && rr > 0.0) {
        if (!timeForAnIteration()) break;
        const double before = elapsed();
        double unused = 0.0;
        const std::vector<double> ap = matrix.apply(p, /*residual=*/false, unused);  // G^T G p
        passDone();
        const double pap = dot(p, ap);
        if (!(pap > 0.0) || !std::isfinite(pap)) break;
        const double alpha = rr / pap;
        for (std::size_t k = 0; k < a.size(); ++k) {
            a[k] += alpha * p[k];
            r[k] -= alpha * ap[k];
        }
        const double next = dot(r, r);
        const double beta = next / rr;
        for (std::size_t k = 0; k < p.size(); ++k) p[k] = r[k] + beta * p[k];
        rr = next;
        ++report.iterations;
        passSeconds = elapsed() - before;
    }
    matrix.apply(a, /*residual=*/true, squared);
    passDone();
    report.mseAfter = squared / values;
    if (report.mseAfter < report.mseBefore &&
        std::all_of(a.begin(), a.end(), [](double v) { return std::isfinite(v); })) {
        setAmplitudes(params, a);
    } else {
        report.mseAfter = report.mseBefore;
    }
    report.seconds = elapsed();
    return report;
}

}  // namespace gvr
