// Dense float volumes: their layout, what a grid becomes (values, foreground and
// placement), and trilinear resampling with its edge clamping.

#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace gvr {
namespace {

TEST(FloatVolume, LayoutIsIFastestWithChannelsInterleaved) {
    FloatVolume v(openvdb::Coord(4, 3, 2), 3);
    EXPECT_EQ(v.voxelCount(), 24u);
    ASSERT_EQ(v.values.size(), 72u);
    for (float value : v.values) EXPECT_EQ(value, 0.0f);
    EXPECT_TRUE(v.foreground.empty());
    EXPECT_EQ(v.indexOf(1, 2, 1), std::size_t((1 * 3 + 2) * 4 + 1));
    EXPECT_EQ(v.at(1, 2, 1) - v.values.data(), 21 * 3);
    v.at(3, 2, 1)[2] = 9.0f;
    EXPECT_EQ(v.values.back(), 9.0f);
}

TEST(FloatVolume, VolumeBoxIsTheSourceBoxWhenIngested) {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    grid->tree().setValue(openvdb::Coord(5, 2, 4), 1.0f);
    EXPECT_EQ(volumeBox(*grid), openvdb::CoordBBox(openvdb::Coord(1, 2, 3), openvdb::Coord(5, 2, 4)));
    // Ingest leaves the background inactive; the box must still cover the whole source.
    VolumeMetadata metadata;
    metadata.sourceType = "uint8";
    metadata.dims = openvdb::Vec3i(10, 8, 6);
    writeVolumeMetadata(metadata, *grid);
    EXPECT_EQ(volumeBox(*grid), openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(9, 7, 5)));
}

TEST(FloatVolume, SampleGridTakesValuesForegroundAndPlacement) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(7.0f);
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 40.0f);
    grid->tree().setValue(openvdb::Coord(2, 2, 3), -5.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(2.0));
    const openvdb::CoordBBox box(openvdb::Coord(1, 2, 3), openvdb::Coord(3, 3, 3));
    const FloatVolume v = sampleGrid(*grid, box);
    EXPECT_EQ(v.dims, openvdb::Coord(3, 2, 1));
    EXPECT_EQ(v.channels, 1);
    ASSERT_EQ(v.values.size(), 6u);
    EXPECT_EQ(v.at(0, 0, 0)[0], 40.0f);
    EXPECT_EQ(v.at(1, 0, 0)[0], -5.0f);
    EXPECT_EQ(v.at(2, 1, 0)[0], 7.0f);  // inactive: the background value
    EXPECT_EQ(v.foreground, (std::vector<std::uint8_t>{1, 1, 0, 0, 0, 0}));
    // Sample (0, 0, 0) is voxel box.min(), 2 mm voxels.
    const openvdb::Vec3d origin = v.worldFromIndex.transform(openvdb::Vec3d(0.0));
    const openvdb::Vec3d next = v.worldFromIndex.transform(openvdb::Vec3d(1.0, 0.0, 0.0));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(origin[a], 2.0 * box.min()[a], 1e-12) << a;
    EXPECT_NEAR(next[0] - origin[0], 2.0, 1e-12);
}

TEST(FloatVolume, SampleGridReadsDoubleAndColourGrids) {
    openvdb::DoubleGrid::Ptr doubles = openvdb::DoubleGrid::create(0.0);
    doubles->tree().setValue(openvdb::Coord(0, 0, 0), 0.25);
    const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0), openvdb::Coord(1, 0, 0));
    const FloatVolume grey = sampleGrid(*doubles, box);
    EXPECT_EQ(grey.channels, 1);
    EXPECT_EQ(grey.at(0, 0, 0)[0], 0.25f);

    openvdb::Vec3SGrid::Ptr colours = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    colours->tree().setValue(openvdb::Coord(1, 0, 0), openvdb::Vec3s(1.0f, 2.0f, 3.0f));
    const FloatVolume rgb = sampleGrid(*colours, box);
    EXPECT_EQ(rgb.channels, 3);
    ASSERT_EQ(rgb.values, (std::vector<float>{0, 0, 0, 1, 2, 3}));
    EXPECT_EQ(rgb.foreground, (std::vector<std::uint8_t>{0, 1}));
}

TEST(FloatVolume, SampleGridRefusesOtherValueTypesNamingTheGrid) {
    openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(0);
    labels->setName("labels");
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(1));
    const std::string message = test::errorMessageOf<InputError>([&] { sampleGrid(*labels, box); });
    EXPECT_NE(message.find("'labels'"), std::string::npos) << message;
}

TEST(FloatVolume, SampleGridOfAnEmptyBoxIsEmpty) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(1.0f);
    const FloatVolume v = sampleGrid(*grid, openvdb::CoordBBox());
    EXPECT_EQ(v.voxelCount(), 0u);
    EXPECT_TRUE(v.values.empty());
    EXPECT_TRUE(v.foreground.empty());
}

FloatVolume ramp() {
    FloatVolume source(openvdb::Coord(2, 1, 1), 1);
    source.values = {0.0f, 10.0f};
    return source;
}

TEST(FloatVolume, ResampleInterpolatesAndClampsToTheEdge) {
    // Target voxel i sits at source x = i / 2 - 1.
    openvdb::math::Mat4d worldFromIndex;
    worldFromIndex.setToScale(openvdb::Vec3d(0.5, 1.0, 1.0));
    worldFromIndex.setTranslation(openvdb::Vec3d(-1.0, 0.0, 0.0));
    const FloatVolume out = resampleTrilinear(ramp(), openvdb::Coord(6, 1, 1), worldFromIndex);
    ASSERT_EQ(out.values.size(), 6u);
    const float expected[6] = {0.0f, 0.0f, 0.0f, 5.0f, 10.0f, 10.0f};
    for (int i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(out.at(i, 0, 0)[0], expected[i]) << i;
    EXPECT_EQ(out.worldFromIndex, worldFromIndex);
}

TEST(FloatVolume, ResampleFarOutsideTakesTheEdgeWithoutOverflow) {
    // 1e12 voxels away would overflow an int before the clamp.
    for (const double x : {1e12, -1e12}) {
        openvdb::math::Mat4d worldFromIndex = openvdb::math::Mat4d::identity();
        worldFromIndex.setTranslation(openvdb::Vec3d(x, -x, x));
        const FloatVolume out = resampleTrilinear(ramp(), openvdb::Coord(1, 1, 1), worldFromIndex);
        EXPECT_EQ(out.at(0, 0, 0)[0], x > 0 ? 10.0f : 0.0f) << x;
    }
}

}  // namespace
}  // namespace gvr
