// The share of a subject's inside that a threshold removed.

#include "pipeline/ThresholdHoles.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

/// A 9 x 9 x 2 square ring of active voxels, two voxels thick, around a 5 x 5 hole
/// (the lungs), with one more active voxel in the hole.
openvdb::FloatGrid::Ptr ringAroundAHole() {
    auto grid = openvdb::FloatGrid::create(-1000.0f);
    for (int z = 0; z < 2; ++z) {
        for (int y = 0; y < 9; ++y) {
            for (int x = 0; x < 9; ++x) {
                const bool hole = x >= 2 && x <= 6 && y >= 2 && y <= 6;
                if (!hole) grid->tree().setValueOn(openvdb::Coord(x, y, z), 40.0f);
            }
        }
    }
    grid->tree().setValueOn(openvdb::Coord(4, 4, 0), 40.0f);
    return grid;
}

TEST(ThresholdHoles, CountsTheInactiveVoxelsThatActiveOnesEncloseInTheirSlice) {
    // Inside: all 81 voxels of each slice; inactive: 24 and 25 of the hole.
    EXPECT_DOUBLE_EQ(enclosedInactiveShare(*ringAroundAHole()), (24.0 + 25.0) / 162.0);
}

TEST(ThresholdHoles, AnOpenSubjectOrAnEmptyGridEnclosesNothing) {
    auto grid = ringAroundAHole();
    grid->tree().setValueOn(openvdb::Coord(4, 0, 0), 40.0f);
    grid->tree().setValueOff(openvdb::Coord(4, 0, 0));  // a gap in the ring: the hole of slice 0 is outside
    grid->tree().setValueOff(openvdb::Coord(4, 1, 0));
    EXPECT_DOUBLE_EQ(enclosedInactiveShare(*grid), 25.0 / (81.0 - 2.0 - 24.0 + 81.0));
    EXPECT_EQ(enclosedInactiveShare(*openvdb::FloatGrid::create()), 0.0);
}

}  // namespace
}  // namespace gvr
