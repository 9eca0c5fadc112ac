// The least-squares amplitude solve: exact on a field it can represent, never worse,
// the same on any thread count, and blind to the voxels it is told to leave out.

#include "pipeline/AmplitudeSolver.h"
#include "pipeline/FieldAccuracy.h"
#include "pipeline/GaussianField.h"
#include "tests/TestHelpers.h"

#include <tbb/global_control.h>

#include <cmath>

namespace gvr {
namespace {

constexpr std::array<int, 3> kDims{28, 24, 20};

/// A volume that is exactly the field of @a params (times 100, so that the ingest's
/// normalisation is a plain scale).
openvdb::GridBase::Ptr gridOfField(const GaussianParameters& params) {
    const GaussianField field(params, 3.0f);
    return test::makeGrid(kDims, [&](int i, int j, int k) {
        std::vector<std::uint32_t> hits;
        const float x[3] = {float(i), float(j), float(k)};
        float value;
        field.evaluate(x, &value, hits);
        return 100.0f * value;
    });
}

/// The same geometry with every colour scaled by a different wrong factor.
GaussianParameters withWrongAmplitudes(GaussianParameters params) {
    for (std::size_t i = 0; i < params.count(); ++i) params.at(kColours, i)[0] *= 0.5f + 0.1f * float(i % 7);
    return params;
}

double psnrOf(const GaussianParameters& params, const VolumeTarget& target) {
    return measureFieldAccuracy(GaussianField(params, 3.0f), target).psnr;
}

TEST(AmplitudeSolver, RecoversTheAmplitudesOfARepresentableField) {
    const GaussianParameters truth = test::randomGaussians(40, 1, 20.0f, 5);
    const VolumeTarget target(gridOfField(truth), "field");
    GaussianParameters params = withWrongAmplitudes(truth);
    const double before = psnrOf(params, target);
    AmplitudeSolveSettings settings;
    settings.iterations = 60;
    const AmplitudeSolveReport report = solveAmplitudes(params, target, settings);
    const double after = psnrOf(params, target);
    EXPECT_LT(before, 35.0);
    EXPECT_GT(after, 70.0) << "before " << before << " dB";
    EXPECT_LT(report.mseAfter, report.mseBefore);
    // The means, rotations and scales are untouched.
    for (ParameterGroup g : {kMeans, kRotations, kLogScales, kOpacityLogits})
        EXPECT_EQ(params.values[g], truth.values[g]);
}

TEST(AmplitudeSolver, LowersTheErrorOnAFieldItCannotRepresent) {
    const VolumeTarget target(
        test::makeGrid(kDims, [](int i, int j, int k) { return float((i * 7 + j * 3 + k) % 11); }), "stripes");
    GaussianParameters params = test::randomGaussians(60, 1, 24.0f, 9);
    const double before = psnrOf(params, target);
    const AmplitudeSolveReport report = solveAmplitudes(params, target, {});
    EXPECT_GT(report.iterations, 0u);
    EXPECT_LT(report.mseAfter, report.mseBefore);
    EXPECT_GT(psnrOf(params, target), before);
}

TEST(AmplitudeSolver, SameResultWhateverTheThreadCount) {
    const VolumeTarget target(gridOfField(test::randomGaussians(30, 1, 20.0f, 3)), "field");
    const GaussianParameters start = test::randomGaussians(30, 1, 20.0f, 4);
    GaussianParameters one = start, two = start;
    {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
        solveAmplitudes(one, target, {});
    }
    {
        tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
        solveAmplitudes(two, target, {});
    }
    EXPECT_EQ(one.values[kColours], two.values[kColours]);
}

TEST(AmplitudeSolver, ExcludedVoxelsDoNotCount) {
    const GaussianParameters truth = test::randomGaussians(30, 1, 20.0f, 6);
    const openvdb::Coord spike(12, 10, 9);
    const GaussianField field(truth, 3.0f);
    // The same field with one voxel far off: left out, it must not pull the solution.
    const VolumeTarget spiked(test::makeGrid(kDims,
                                             [&](int i, int j, int k) {
                                                 std::vector<std::uint32_t> hits;
                                                 const float x[3] = {float(i), float(j), float(k)};
                                                 float value;
                                                 field.evaluate(x, &value, hits);
                                                 return 100.0f * value +
                                                        (openvdb::Coord(i, j, k) == spike ? 500.0f : 0.0f);
                                             }),
                              "spiked");
    GaussianParameters params = withWrongAmplitudes(truth);
    AmplitudeSolveSettings settings;
    settings.iterations = 60;
    settings.excluded = {spike};
    solveAmplitudes(params, spiked, settings);
    // Compare away from the spike: the solution is the true field's.
    float worst = 0.0f;
    const GaussianField solved(params, 3.0f);
    std::vector<std::uint32_t> hits;
    for (int k = 0; k < kDims[2]; ++k) {
        for (int j = 0; j < kDims[1]; ++j) {
            for (int i = 0; i < kDims[0]; ++i) {
                if (openvdb::Coord(i, j, k) == spike) continue;
                const float x[3] = {float(i), float(j), float(k)};
                float want, got;
                field.evaluate(x, &want, hits);
                solved.evaluate(x, &got, hits);
                worst = std::max(
                    worst, std::abs(100.0f * want - float(spiked.mapping().offset[0] + spiked.mapping().scale * got)));
            }
        }
    }
    EXPECT_LT(worst, 0.05f);
}

}  // namespace
}  // namespace gvr
