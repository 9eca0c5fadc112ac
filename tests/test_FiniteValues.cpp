// A .vdb read as it stands must hold finite values everywhere a sampler may read:
// active and inactive voxels, tiles and the background.

#include "pipeline/Error.h"
#include "pipeline/FiniteValues.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

openvdb::FloatGrid::Ptr blockOfOnes() {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->denseFill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)), 1.0f, /*active=*/true);
    return grid;
}

std::string failure(const openvdb::GridBase& grid, const std::optional<openvdb::CoordBBox>& region = std::nullopt) {
    try {
        requireFiniteValues(grid, "v.vdb", region);
    } catch (const InputError& error) {
        return error.what();
    }
    return "";
}

TEST(FiniteValues, FiniteGridsPass) {
    EXPECT_EQ(failure(*blockOfOnes()), "");
    auto extremes = blockOfOnes();
    extremes->tree().setValueOn(openvdb::Coord(1), 3.4e38f);
    extremes->tree().setValueOn(openvdb::Coord(2), 1e-45f);
    EXPECT_EQ(failure(*extremes), "");
}

TEST(FiniteValues, NonFiniteVoxelsActiveOrNotAreCountedAndLocated) {
    auto grid = blockOfOnes();
    grid->tree().setValueOn(openvdb::Coord(3, 4, 5), NAN);
    grid->tree().setValueOff(openvdb::Coord(9, 9, 9), INFINITY);  // inactive, but trilinear reads see it
    const std::string message = failure(*grid);
    EXPECT_NE(message.find("v.vdb: grid 'density' holds 2 NaN or infinite values"), std::string::npos) << message;
    EXPECT_NE(message.find("[3, 4, 5]"), std::string::npos) << message;
    EXPECT_NE(message.find("`nan_to=VALUE`"), std::string::npos) << message;
    // A region away from them passes; one that touches their leaf does not.
    EXPECT_EQ(failure(*grid, openvdb::CoordBBox(openvdb::Coord(8, 0, 0), openvdb::Coord(15, 7, 7))), "");
    EXPECT_NE(failure(*grid, openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(2))), "");
}

TEST(FiniteValues, NonFiniteTilesAndBackgroundsAreRefused) {
    auto tiled = blockOfOnes();
    tiled->tree().addTile(/*level=*/1, openvdb::Coord(128, 0, 0), -INFINITY, /*active=*/false);
    EXPECT_NE(failure(*tiled).find("holds 1 NaN"), std::string::npos) << failure(*tiled);
    auto background = openvdb::FloatGrid::create(NAN);
    background->setName("density");
    background->tree().setValueOn(openvdb::Coord(0), 1.0f);
    EXPECT_NE(failure(*background).find("NaN or infinite background"), std::string::npos);
}

TEST(FiniteValues, ColourAndDoubleGridsAreCheckedToo) {
    auto colour = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    colour->setName("color");
    colour->tree().setValueOn(openvdb::Coord(1), openvdb::Vec3s(0.5f, NAN, 0.5f));
    EXPECT_NE(failure(*colour).find("grid 'color' holds 1"), std::string::npos);
    auto doubles = openvdb::DoubleGrid::create(0.0);
    doubles->tree().setValueOn(openvdb::Coord(1), INFINITY);
    EXPECT_NE(failure(*doubles), "");
}

}  // namespace
}  // namespace gvr
