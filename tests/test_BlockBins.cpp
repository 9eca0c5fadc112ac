// The fit's neighbour lists: every Gaussian that reaches a block is in its bin,
// before and after the Gaussians move.

#include "pipeline/BlockBins.h"
#include "tests/TestHelpers.h"

namespace gvr {
namespace {

/// Every Gaussian of @a field whose truncated field is non-zero at a voxel centre
/// of a block, or at a point inside its cells, is listed in that block's bin.
void expectBinsHoldEveryReach(const GaussianField& field, const BlockBins& bins) {
    const BlockGrid& grid = bins.grid();
    for (std::uint32_t b = 0; b < grid.blockCount(); ++b) {
        const std::vector<std::uint32_t>& bin = bins.gaussians(b);
        ASSERT_TRUE(std::is_sorted(bin.begin(), bin.end()));
        const openvdb::Coord o = grid.origin(b);
        for (std::uint32_t g = 0; g < field.gaussians().size(); ++g) {
            bool reaches = false;
            for (int k = 0; k < 9 * 9 * 9 && !reaches; ++k) {  // corners of the cells, and centres
                const float x[3] = {o.x() - 0.5f + (k % 9) * 0.999f, o.y() - 0.5f + (k / 9 % 9) * 0.999f,
                                    o.z() - 0.5f + (k / 81) * 0.999f};
                float u[3];
                reaches = mahalanobis2(field.gaussians()[g], x, u) <= field.cutoff2();
            }
            if (reaches) {
                EXPECT_TRUE(std::binary_search(bin.begin(), bin.end(), g)) << "Gaussian " << g << ", block " << b;
            }
        }
    }
}

TEST(BlockBins, EveryGaussianThatReachesABlockIsInItsBin) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(-2, 0, 1), openvdb::Coord(29, 21, 18)));
    const GaussianField field(test::randomGaussians(60, 1, 24.0f, 7), 3.0f, false);
    BlockBins bins(grid, 0.0f, 0.0f);
    bins.build(field);
    expectBinsHoldEveryReach(field, bins);
    EXPECT_LT(bins.pairCount(), grid.blockCount() * 60) << "bins that hold everything test nothing";
}

TEST(BlockBins, GaussiansThatMoveOutAreFollowedWithoutRebinningTheRest) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(31, 23, 23)));
    GaussianParameters params = test::randomGaussians(40, 1, 22.0f, 11);
    GaussianField field;
    field.rebuild(params, 3.0f, true, 0.5f, 0.05f);
    BlockBins bins(grid, 0.5f, 0.05f);
    bins.build(field);
    const std::size_t pairsBefore = bins.pairCount();
    // Three Gaussians move far; one grows; the rest stay.
    params.at(kMeans, 3)[0] += 9.0f;
    params.at(kMeans, 17)[1] -= 7.5f;
    params.at(kMeans, 30)[2] += 12.0f;
    params.at(kLogScales, 8)[1] += 1.0f;
    for (std::size_t i = 0; i < params.count(); ++i) field.reactivate(params, i);
    EXPECT_EQ(bins.follow(field), 4u);
    EXPECT_GT(bins.pairCount(), pairsBefore);
    expectBinsHoldEveryReach(field, bins);
    EXPECT_EQ(bins.follow(field), 0u) << "a Gaussian followed once stays inside its new box";
}

TEST(BlockBins, PointsFindTheGaussiansThatReachThem) {
    const BlockGrid grid(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(19, 17, 16)));
    const GaussianField field(test::randomGaussians(30, 1, 18.0f, 5), 3.0f);
    BlockBins bins(grid, 0.0f, 0.0f);
    bins.build(field);
    std::vector<std::uint32_t> hits;
    for (int k = 0; k < 2000; ++k) {
        const float x[3] = {float(k % 19) + 0.37f * float(k % 3), float(k % 17) + 0.21f, float(k % 16) + 0.49f};
        field.bvh().query(x, hits);
        const std::vector<std::uint32_t>& near = bins.gaussiansNear(x);
        for (std::uint32_t g : hits) EXPECT_TRUE(std::binary_search(near.begin(), near.end(), g));
    }
}

}  // namespace
}  // namespace gvr
