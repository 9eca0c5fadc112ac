// Uniform voxels of a box: inside it, reproducible from the seed, and spread over it.

#include "pipeline/UniformVoxels.h"

#include <gtest/gtest.h>

#include <map>

namespace gvr {
namespace {

TEST(UniformVoxels, StayInTheBoxRepeatFromTheSeedAndCoverIt) {
    const openvdb::CoordBBox box(openvdb::Coord(-5, 10, 0), openvdb::Coord(4, 13, 1));  // 10 x 4 x 2 voxels
    const std::vector<openvdb::Coord> a = drawUniformVoxels(box, 8000, 3);
    EXPECT_EQ(a, drawUniformVoxels(box, 8000, 3));
    EXPECT_NE(a, drawUniformVoxels(box, 8000, 4));
    std::map<openvdb::Coord, int> hits;
    for (const openvdb::Coord& ijk : a) {
        ASSERT_TRUE(box.isInside(ijk)) << ijk;
        ++hits[ijk];
    }
    ASSERT_EQ(hits.size(), 80u);  // every voxel drawn
    for (const auto& [ijk, count] : hits) {
        EXPECT_GT(count, 60) << ijk;  // 100 expected each; a 4-sigma band
        EXPECT_LT(count, 140) << ijk;
    }
}

}  // namespace
}  // namespace gvr
