// The orbit camera: which way it looks, its axes, and how it frames a box.

#include "pipeline/Error.h"
#include "render/Camera.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace gvr;

namespace {

void expectNear(const openvdb::Vec3d& got, const openvdb::Vec3d& want, const char* what) {
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], want[a], 1e-9) << what << " axis " << a;
}

/// A box of 40 x 100 x 60 mm, not centred on the origin.
std::array<openvdb::Vec3d, 8> box() {
    openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
    worldFromIndex.preScale(openvdb::Vec3d(2.0, 5.0, 3.0));
    worldFromIndex.postTranslate(openvdb::Vec3d(10.0, -20.0, 7.0));
    return worldCorners(worldFromIndex, openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(19)));
}

/// Where a world point lands in the image, in pixels from the top left corner.
openvdb::Vec2d imagePoint(const OrthoCamera& camera, const openvdb::Vec3d& p) {
    return {(p - camera.centre).dot(camera.right) / camera.pixelMm + 0.5 * camera.width,
            0.5 * camera.height - (p - camera.centre).dot(camera.up) / camera.pixelMm};
}

}  // namespace

TEST(Camera, TheFrontViewLooksAtTheFaceWithThePatientsRightOnTheImagesLeft) {
    const OrthoCamera camera = makeCamera({0.0, 0.0}, box(), 64, 64);
    expectNear(camera.direction, {0, -1, 0}, "rays travel posterior");
    expectNear(camera.right, {-1, 0, 0}, "the image's x runs to the patient's left (RAS: -x)");
    expectNear(camera.up, {0, 0, 1}, "superior is up");
    // A quarter turn of azimuth looks from +x, the patient's right in RAS, instead.
    expectNear(makeCamera({90.0, 0.0}, box(), 64, 64).direction, {-1, 0, 0}, "from the right");
}

TEST(Camera, HugeFiniteAnglesAreRefusedAsBadInput) {
    // Before, 6e307 degrees overflowed to an infinite number of radians: "Normalizing
    // null 3-vector", an internal error.
    for (const double angle : {6e307, -1.7e308, 1e6 + 1}) {
        EXPECT_THROW(makeCamera({angle, 0.0}, box(), 32, 32), InputError) << angle;
        EXPECT_THROW(makeCamera({0.0, angle}, box(), 32, 32), InputError) << angle;
    }
    expectNear(makeCamera({1e6, 0.0}, box(), 32, 32).direction,
               makeCamera({std::fmod(1e6, 360.0), 0.0}, box(), 32, 32).direction, "2,777 turns and 280 degrees");
}

TEST(Camera, AxesAreOrthonormalAndElevationLiftsTheCameraTowardsSuperior) {
    for (const double azimuth : {-170.0, -45.0, 0.0, 30.0, 123.0, 400.0}) {
        for (const double elevation : {-89.0, -20.0, 0.0, 35.0, 90.0}) {
            SCOPED_TRACE(std::to_string(azimuth) + ", " + std::to_string(elevation));
            const OrthoCamera c = makeCamera({azimuth, elevation}, box(), 32, 48);
            for (const openvdb::Vec3d* axis : {&c.direction, &c.right, &c.up}) EXPECT_NEAR(axis->length(), 1.0, 1e-9);
            EXPECT_NEAR(c.direction.dot(c.right), 0.0, 1e-9);
            EXPECT_NEAR(c.direction.dot(c.up), 0.0, 1e-9);
            EXPECT_NEAR(c.right.dot(c.up), 0.0, 1e-9);
            EXPECT_NEAR(c.direction.z(), -std::sin(elevation * M_PI / 180.0), 1e-9);
            if (std::abs(elevation) < 90.0) {
                EXPECT_GT(c.up.z(), 0.0);
            }
        }
    }
}

TEST(Camera, TheBoxFillsTheImageUpToATwoPercentMarginOnItsTighterAxis) {
    for (const auto& [width, height] : {std::pair{64, 64}, std::pair{200, 50}, std::pair{30, 300}}) {
        for (const double azimuth : {0.0, 37.0, 90.0}) {
            SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " at " + std::to_string(azimuth));
            const OrthoCamera camera = makeCamera({azimuth, 20.0}, box(), width, height);
            double lowX = 1e9, highX = -1e9, lowY = 1e9, highY = -1e9;
            for (const openvdb::Vec3d& corner : box()) {
                const openvdb::Vec2d p = imagePoint(camera, corner);
                lowX = std::min(lowX, p.x()), highX = std::max(highX, p.x());
                lowY = std::min(lowY, p.y()), highY = std::max(highY, p.y());
            }
            EXPECT_GE(lowX, 0.0);
            EXPECT_LE(highX, width);
            EXPECT_GE(lowY, 0.0);
            EXPECT_LE(highY, height);
            const double fill = std::max((highX - lowX) / width, (highY - lowY) / height);
            EXPECT_NEAR(fill, 1.0 / 1.02, 1e-9);
            // The box's centre is the image's centre.
            EXPECT_NEAR(0.5 * (lowX + highX), 0.5 * width, 1e-9);
            EXPECT_NEAR(0.5 * (lowY + highY), 0.5 * height, 1e-9);
        }
    }
}

TEST(Camera, CornersAreTheVoxelCellsOuterFacesAndBadRequestsAreRefused) {
    const std::array<openvdb::Vec3d, 8> corners = box();
    expectNear(corners[0], {10.0 - 1.0, -20.0 - 2.5, 7.0 - 1.5}, "index -0.5 of the first voxel");
    expectNear(corners[7], {10.0 + 39.0, -20.0 + 97.5, 7.0 + 58.5}, "index 19.5 of the last");
    EXPECT_THROW(makeCamera({0.0, 0.0}, corners, 0, 10), InputError);
    EXPECT_THROW(makeCamera({0.0, 0.0}, corners, kMaxImageSide + 1, 10), InputError);
    EXPECT_THROW(makeCamera({NAN, 0.0}, corners, 10, 10), InputError);
    EXPECT_THROW(makeCamera({0.0, INFINITY}, corners, 10, 10), InputError);
    EXPECT_NEAR(angleBetweenDeg({1, 0, 0}, {0, 1, 0}), 90.0, 1e-12);
    EXPECT_EQ(angleBetweenDeg({1, 0, 0}, {1 + 1e-15, 0, 0}), 0.0) << "a dot product past 1 by rounding is no NaN";
}
