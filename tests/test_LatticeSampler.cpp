// Block sampling on arbitrary lattices: the skip bound never hides a value above it.

#include "pipeline/LatticeSampler.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace gvr {
namespace {

/// An oblique lattice, 0.7 voxels apart, over the field and beyond it.
Lattice obliqueLattice() {
    openvdb::math::Mat4d worldFromLattice = openvdb::math::Mat4d::identity();
    worldFromLattice.setToRotation(openvdb::Vec3d(1, 2, 3).unit(), 0.6);
    worldFromLattice.preScale(openvdb::Vec3d(0.7));
    worldFromLattice.setTranslation(openvdb::Vec3d(-5.0));
    return {worldFromLattice, openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(71))};
}

TEST(LatticeSampler, ObliqueLatticesHoldExactlyThePointEvaluation) {
    const GaussianField field(test::randomGaussians(300, 1, 40.0f, 22), 3.0f);
    const Lattice lattice = obliqueLattice();
    const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(), lattice, openvdb::CoordBBox::inf());
    std::vector<std::uint32_t> hits;
    std::size_t nonZero = 0;
    for (const openvdb::Coord& origin : sampler.occupiedBlocks()) {
        float sums[kBlockVoxels] = {};
        const openvdb::CoordBBox voxels = sampler.sampleBlock(origin, sums);
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            const openvdb::Vec3d p = lattice.worldFromIndex.transform((*ijk).asVec3d());
            const float x[3] = {float(p[0]), float(p[1]), float(p[2])};
            float expected;
            field.evaluate(x, &expected, hits);
            ASSERT_EQ(sums[blockOffset(*ijk)], expected) << *ijk;
            nonZero += expected != 0.0f;
        }
    }
    EXPECT_GT(nonZero, 10000u);
}

// One Gaussian at a time, so that every difference belongs to one term.
TEST(LatticeSampler, RowEvaluationKeepsEachTermWithinItsToleranceOfExact) {
    const GaussianParameters all = test::randomGaussians(60, 3, 12.0f, 24);
    const Lattice lattice = obliqueLattice();
    std::size_t nonZero = 0, atEdge = 0;
    for (std::size_t n = 0; n < all.count(); ++n) {
        GaussianParameters one = all;
        std::vector<bool> keep(all.count(), false);
        keep[n] = true;
        one.keepOnly(keep);
        const GaussianField field(one, 3.0f);
        const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(), lattice, openvdb::CoordBBox::inf());
        const float peak = peakAmplitude(one, 0);
        for (const openvdb::Coord& origin : sampler.occupiedBlocks()) {
            float exact[kBlockVoxels * 3] = {}, rows[kBlockVoxels * 3] = {};
            const openvdb::CoordBBox voxels = sampler.sampleBlock(origin, exact);
            ASSERT_EQ(sampler.sampleBlock(origin, rows, -1.0f, BlockEvaluation::Rows), voxels);
            for (auto ijk = voxels.begin(); ijk; ++ijk) {
                for (int c = 0; c < 3; ++c) {
                    const float e = exact[blockOffset(*ijk) * 3 + c], r = rows[blockOffset(*ijk) * 3 + c];
                    nonZero += e != 0.0f;
                    if (std::abs(r - e) <= 1e-5f * peak) continue;
                    // Only a term that one keeps and the other cuts, at the truncation edge.
                    ++atEdge;
                    ASSERT_TRUE(r == 0.0f || e == 0.0f) << *ijk << ": " << r << " against " << e;
                    ASSERT_LE(std::abs(r - e), 1.02f * std::exp(-4.5f) * peak) << *ijk;
                }
            }
        }
    }
    EXPECT_GT(nonZero, 100000u);
    EXPECT_LE(atEdge, nonZero / 10000);
}

// Rows are evaluated eight samples at a time where the processor has AVX2 and
// four at a time elsewhere: the same floats either way, grey or colour.
TEST(LatticeSampler, RowEvaluationIsTheSameFourOrEightSamplesAtATime) {
    const Lattice lattice = obliqueLattice();
    for (int channels : {1, 3}) {
        const GaussianField field(test::randomGaussians(300, channels, 40.0f, 25), 3.0f);
        const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(), lattice, openvdb::CoordBBox::inf());
        std::size_t nonZero = 0;
        for (const openvdb::Coord& origin : sampler.occupiedBlocks()) {
            float rows[kBlockVoxels * 3] = {}, fourLanes[kBlockVoxels * 3] = {};
            const openvdb::CoordBBox voxels = sampler.sampleBlock(origin, rows, -1.0f, BlockEvaluation::Rows);
            ASSERT_EQ(sampler.sampleBlock(origin, fourLanes, -1.0f, BlockEvaluation::RowsFourLanes), voxels);
            for (int n = 0; n < kBlockVoxels * channels; ++n) {
                ASSERT_EQ(rows[n], fourLanes[n]) << origin << " value " << n;
                nonZero += rows[n] != 0.0f;
            }
        }
        EXPECT_GT(nonZero, 10000u) << channels << " channels";
    }
}

TEST(LatticeSampler, SkippedBlocksNeverHoldValuesAboveTheBound) {
    const GaussianField field(test::randomGaussians(300, 1, 40.0f, 21), 3.0f);
    const Lattice lattice = obliqueLattice();
    const LatticeSampler sampler(field, openvdb::math::Mat4d::identity(), lattice, openvdb::CoordBBox::inf());
    std::size_t skipped = 0, kept = 0;
    for (const float bound : {0.05f, 0.2f, 0.5f}) {
        for (const openvdb::Coord& origin : sampler.occupiedBlocks()) {
            float exact[kBlockVoxels] = {}, maybe[kBlockVoxels] = {};
            const openvdb::CoordBBox voxels = sampler.sampleBlock(origin, exact);
            if (!sampler.sampleBlock(origin, maybe, bound).empty()) {
                ++kept;
                ASSERT_TRUE(std::equal(exact, exact + kBlockVoxels, maybe));  // sampled blocks are exact
                continue;
            }
            ++skipped;
            for (auto ijk = voxels.begin(); ijk; ++ijk) ASSERT_LE(exact[blockOffset(*ijk)], bound) << *ijk;
        }
    }
    EXPECT_GT(skipped, 10u);  // the bound is tight enough to matter
    EXPECT_GT(kept, 10u);
}

TEST(BlockLists, HoldEveryBoxThatMeetsABlockInAscendingOrder) {
    const openvdb::CoordBBox box(openvdb::Coord(-20, -3, 0), openvdb::Coord(30, 25, 40));
    const BlockSlots slots(box);
    std::vector<openvdb::CoordBBox> reach;
    std::mt19937 random(5);
    std::uniform_int_distribution<int> corner(-20, 30), size(0, 12);
    for (int g = 0; g < 400; ++g) {
        const openvdb::Coord low(corner(random), corner(random), corner(random));
        openvdb::CoordBBox r(low, low + openvdb::Coord(size(random), size(random), size(random)));
        r.intersect(box);  // as the sampler keeps them; some end up empty
        reach.push_back(r);
    }
    const BlockLists lists(reach, slots);
    const std::vector<openvdb::Coord> origins = blockOrigins(box);
    std::size_t pairs = 0;
    for (std::size_t slot = 0; slot < origins.size(); ++slot) {
        const openvdb::CoordBBox block(origins[slot], origins[slot] + openvdb::Coord(kBlockDim - 1));
        std::vector<std::uint32_t> expected;
        for (std::uint32_t g = 0; g < reach.size(); ++g) {
            if (!reach[g].empty() && reach[g].hasOverlap(block)) expected.push_back(g);
        }
        EXPECT_EQ(std::vector<std::uint32_t>(lists.begin(slot), lists.end(slot)), expected) << origins[slot];
        EXPECT_EQ(lists.count(slot), expected.size());
        pairs += expected.size();
    }
    EXPECT_GT(pairs, reach.size());  // boxes that straddle blocks are listed in each
}

}  // namespace
}  // namespace gvr
