// The bricks' tapers: one inside a core far from faces, fading across a face, and
// the weights of a lattice of bricks adding up to one at every voxel.

#include "pipeline/Taper.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

const openvdb::CoordBBox kVolume(openvdb::Coord(0), openvdb::Coord(31, 15, 15));

/// Two bricks of kVolume cut at x = 16, fading over @a width voxels.
std::array<Taper, 2> twoBricks(int width) {
    return {Taper{openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15, 15, 15)), kVolume, width},
            Taper{openvdb::CoordBBox(openvdb::Coord(16, 0, 0), openvdb::Coord(31, 15, 15)), kVolume, width}};
}

TEST(Taper, TheWeightsOfNeighboursAddUpToOneAcrossTheirFace) {
    const auto bricks = twoBricks(4);
    for (int x = 0; x <= 31; ++x) {
        const openvdb::Coord ijk(x, 7, 7);
        EXPECT_NEAR(bricks[0].at(ijk) + bricks[1].at(ijk), 1.0f, 1e-6f) << x;
    }
    EXPECT_EQ(bricks[0].at({2, 7, 7}), 1.0f);                       // far from the face
    EXPECT_EQ(bricks[0].at({25, 7, 7}), 0.0f);                      // beyond the fade, in the other brick
    EXPECT_GT(bricks[0].at({15, 7, 7}), bricks[0].at({16, 7, 7}));  // falling across the face
}

TEST(Taper, FacesOnTheVolumesBoundaryDoNotFade) {
    const auto bricks = twoBricks(4);
    EXPECT_EQ(bricks[0].at({0, 0, 0}), 1.0f);
    EXPECT_EQ(bricks[1].at({31, 15, 15}), 1.0f);
}

}  // namespace
}  // namespace gvr
