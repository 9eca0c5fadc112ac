// Leaves filled in parallel and linked in order: every leaf arrives whole and in
// its place, missing leaves stay background, and progress counts every origin.

#include "pipeline/LeafAssembly.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <memory>
#include <vector>

namespace gvr {
namespace {

using FloatLeaf = openvdb::FloatGrid::TreeType::LeafNodeType;

TEST(LeafAssembly, LeavesLandAtTheirOriginsAndNullLeavesAreLeftOut) {
    const std::vector<openvdb::Coord> origins{{0, 0, 0}, {8, 0, 0}, {0, 8, 16}, {-8, -8, -8}};
    std::vector<double> fractions;
    const openvdb::FloatGrid::Ptr grid = assembleGrid<openvdb::FloatGrid>(
        origins, -1.0f,
        [](const openvdb::Coord& origin) -> std::unique_ptr<FloatLeaf> {
            if (origin == openvdb::Coord(8, 0, 0)) return nullptr;
            return std::make_unique<FloatLeaf>(origin, float(origin.z() + 1), true);
        },
        [&](double fraction) { fractions.push_back(fraction); });
    EXPECT_EQ(grid->tree().leafCount(), 3u);
    EXPECT_EQ(grid->activeVoxelCount(), 3u * 512u);
    EXPECT_EQ(grid->background(), -1.0f);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(3, 4, 5)), 1.0f);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(7, 15, 23)), 17.0f);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(-1, -1, -1)), -7.0f);  // negative coordinates work too
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(9, 1, 1)));
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(9, 1, 1)), -1.0f);
    // One report per origin, the null leaf's too, rising to 1.
    ASSERT_EQ(fractions.size(), 4u);
    EXPECT_DOUBLE_EQ(fractions.front(), 0.25);
    EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
}

TEST(LeafAssembly, AThousandLeavesFilledConcurrentlyEachHoldTheirOwnValues) {
    std::vector<openvdb::Coord> origins;
    for (int z = 0; z < 10; ++z) {
        for (int y = 0; y < 10; ++y) {
            for (int x = 0; x < 10; ++x) origins.emplace_back(8 * x, 8 * y, 8 * z);
        }
    }
    const auto code = [](const openvdb::Coord& origin) {
        return origin.x() / 8 + 10 * (origin.y() / 8) + 100 * (origin.z() / 8);
    };
    using IntLeaf = openvdb::Int32Grid::TreeType::LeafNodeType;
    const openvdb::Int32Grid::Ptr grid = assembleGrid<openvdb::Int32Grid>(
        origins, -1,
        [&](const openvdb::Coord& origin) { return std::make_unique<IntLeaf>(origin, code(origin), true); });
    ASSERT_EQ(grid->tree().leafCount(), 1000u);
    for (const openvdb::Coord& origin : origins) {
        const IntLeaf* leaf = grid->tree().probeConstLeaf(origin);
        ASSERT_NE(leaf, nullptr) << origin;
        EXPECT_EQ(leaf->origin(), origin);
        EXPECT_EQ(leaf->getValue(openvdb::Coord(7, 7, 7) + origin), code(origin)) << origin;
        EXPECT_TRUE(leaf->isDense()) << origin;
    }
}

TEST(LeafAssembly, AddedLeavesReplaceLeavesAlreadyThere) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValueOn(openvdb::Coord(1, 1, 1), 5.0f);
    grid->tree().setValueOn(openvdb::Coord(20, 1, 1), 6.0f);
    const ProgressFn silent;
    ProgressCounter counter(silent, 1);
    addLeaves(
        *grid, {openvdb::Coord(0, 0, 0)},
        [](const openvdb::Coord& origin) { return std::make_unique<FloatLeaf>(origin, 2.0f, false); }, counter);
    EXPECT_EQ(grid->tree().leafCount(), 2u);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 1, 1)), 2.0f);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(1, 1, 1)));     // the new leaf's state, not a merge
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(20, 1, 1)), 6.0f);  // other leaves are untouched
}

}  // namespace
}  // namespace gvr
