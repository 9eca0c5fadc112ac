// Trilinear interpolation's corners and weights, on which the target, dense resampling
// and the renderer all rely.

#include "pipeline/Trilinear.h"

#include <gtest/gtest.h>

#include <vector>

namespace gvr {
namespace {

struct Visit {
    openvdb::Coord corner;
    double weight;
};

std::vector<Visit> cornersOf(const openvdb::Vec3d& x) {
    std::vector<Visit> visits;
    forEachTrilinearCorner(x, [&](const openvdb::Coord& corner, double weight) { visits.push_back({corner, weight}); });
    return visits;
}

TEST(Trilinear, ReproducesALinearFunctionAndItsCorners) {
    const auto linear = [](const openvdb::Vec3d& p) { return 2.0 * p[0] - 3.0 * p[1] + 0.5 * p[2] + 7.0; };
    for (const openvdb::Vec3d x :
         {openvdb::Vec3d(1.25, 2.5, 3.75), openvdb::Vec3d(-0.5, -1.25, -7.9), openvdb::Vec3d(0, 0, 0.5)}) {
        double sum = 0.0, weights = 0.0;
        for (const Visit& v : cornersOf(x)) {
            EXPECT_GT(v.weight, 0.0);
            for (int a = 0; a < 3; ++a)
                EXPECT_LE(std::abs(double(v.corner[a]) - x[a]), 1.0) << "a corner beyond the cell";
            sum += v.weight * linear(v.corner.asVec3d());
            weights += v.weight;
        }
        EXPECT_NEAR(weights, 1.0, 1e-12);
        EXPECT_NEAR(sum, linear(x), 1e-9) << x;
    }
}

TEST(Trilinear, AVoxelCentreReadsOnlyThatVoxel) {
    const std::vector<Visit> visits = cornersOf(openvdb::Vec3d(-3, 4, 5));
    ASSERT_EQ(visits.size(), 1u);
    EXPECT_EQ(visits[0].corner, openvdb::Coord(-3, 4, 5));
    EXPECT_EQ(visits[0].weight, 1.0);
}

TEST(Trilinear, NegativeCoordinatesRoundDown) {
    // Truncation towards zero would pick the cell on the wrong side of 0.
    const std::vector<Visit> visits = cornersOf(openvdb::Vec3d(-0.25, 0.0, 0.0));
    ASSERT_EQ(visits.size(), 2u);
    EXPECT_EQ(visits[0].corner, openvdb::Coord(-1, 0, 0));
    EXPECT_DOUBLE_EQ(visits[0].weight, 0.25);
    EXPECT_EQ(visits[1].corner, openvdb::Coord(0, 0, 0));
    EXPECT_DOUBLE_EQ(visits[1].weight, 0.75);
}

}  // namespace
}  // namespace gvr
