// The Monte Carlo voxel loss is an unbiased estimate of the dense voxel MSE.

#include "ImportanceSampler.h"
#include "Loss.h"
#include "TestHelpers.h"
#include "VolumeError.h"

#include <cmath>

namespace gvr {
namespace {

TEST(ImportanceSampler, ProbabilitiesSumToOne) {
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(20, 13, 9));
    ImportanceSampler sampler(box, {});
    for (std::uint32_t b = 0; b < sampler.blockCount(); ++b) sampler.setBlockError(b, 0.01 * (b % 5));
    double total = 0.0;
    for (auto ijk = box.begin(); ijk; ++ijk) total += sampler.probability(*ijk);
    EXPECT_NEAR(total, 1.0, 1e-9);
}

TEST(ImportanceSampler, WeightedEstimateOfTheMseIsUnbiased) {
    // A blob the field only roughly matches, so that errors vary across blocks.
    const auto blob = [](int i, int j, int k) {
        const float d2 = float((i - 12) * (i - 12) + (j - 10) * (j - 10) + (k - 9) * (k - 9));
        return 100.0f * std::exp(-d2 / 40.0f) + (i % 3 == 0 ? 5.0f : 0.0f);
    };
    const VolumeTarget target(test::makeGrid({24, 20, 18}, blob), "blob");
    GaussianParameters params(1, 1);
    std::copy_n(std::array<float, 3>{11.0f, 10.0f, 9.0f}.data(), 3, params.at(kMeans, 0));
    params.at(kRotations, 0)[0] = 1.0f;
    std::fill_n(params.at(kLogScales, 0), 3, std::log(4.0f));
    params.at(kColours, 0)[0] = 1.6f;
    const GaussianField field(params, 3.0f);
    const double dense = measureVolumeError(field, target).mse;

    ImportanceSettings settings;
    settings.uniformShare = 0.2;
    ImportanceSampler sampler(target.box(), settings);
    // Steer p_imp to a strongly non-uniform shape.
    for (std::uint32_t b = 0; b < sampler.blockCount(); ++b) sampler.setBlockError(b, b % 4 == 0 ? 1.0 : 0.001);

    constexpr int kDraws = 400;
    constexpr std::size_t kSamples = 500;
    std::vector<double> estimates;
    for (int draw = 0; draw < kDraws; ++draw) {
        SampleSet set;
        for (const VoxelSample& s : sampler.draw(kSamples, 1000 + draw)) {
            set.points.push_back({float(s.ijk.x()), float(s.ijk.y()), float(s.ijk.z())});
            set.weights.push_back(s.weight / float(kSamples));
            float value;
            target.valueAt(s.ijk, &value);
            set.targets.push_back(value);
        }
        estimates.push_back(weightedSquaredError(field, set, 1.0));
    }
    double mean = 0.0;
    for (double e : estimates) mean += e / kDraws;
    double variance = 0.0;
    for (double e : estimates) variance += (e - mean) * (e - mean) / (kDraws - 1);
    const double standardError = std::sqrt(variance / kDraws);
    EXPECT_GT(standardError, 0.0);
    EXPECT_LT(std::abs(mean - dense), 4.0 * standardError)
        << "mean of estimates " << mean << ", dense MSE " << dense << ", standard error " << standardError;
}

TEST(ImportanceSampler, ExcludedVoxelsAreNeverDrawnAndWeightsStayUnbiased) {
    const openvdb::CoordBBox box(openvdb::Coord(-3, 0, 2), openvdb::Coord(12, 9, 11));
    ImportanceSettings settings;
    settings.uniformShare = 0.2;
    ImportanceSampler sampler(box, settings);
    for (std::uint32_t b = 0; b < sampler.blockCount(); ++b) sampler.setBlockError(b, b % 3 == 0 ? 1.0 : 0.01);
    // Exclude every voxel of the first slab: a large, high-error share of p.
    std::vector<openvdb::Coord> excluded;
    for (auto ijk = box.begin(); ijk; ++ijk) {
        if ((*ijk).z() <= 4) excluded.push_back(*ijk);
    }
    sampler.exclude(excluded);

    // E[w] over the remaining voxels is 1 when the weights are right.
    constexpr std::size_t kSamples = 200000;
    double sum = 0.0, sumSquares = 0.0;
    for (const VoxelSample& s : sampler.draw(kSamples, 7)) {
        ASSERT_GT(s.ijk.z(), 4) << "an excluded voxel was drawn";
        sum += s.weight;
        sumSquares += double(s.weight) * s.weight;
    }
    const double mean = sum / kSamples;
    const double standardError = std::sqrt((sumSquares / kSamples - mean * mean) / kSamples);
    EXPECT_LT(std::abs(mean - 1.0), 4.0 * standardError) << "mean weight " << mean;

    std::vector<openvdb::Coord> everything;
    for (auto ijk = box.begin(); ijk; ++ijk) everything.push_back(*ijk);
    EXPECT_THROW(sampler.exclude(everything), std::invalid_argument);
}

}  // namespace
}  // namespace gvr
