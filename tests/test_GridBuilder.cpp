#include "Error.h"
#include "GridBuilder.h"
#include "TestHelpers.h"
#include "VolumeMetadata.h"

#include <cmath>
#include <limits>

namespace gvr {
namespace {

using test::makeVolume;

openvdb::FloatGrid::Ptr asFloat(const openvdb::GridBase::Ptr& grid) {
    auto floats = openvdb::GridBase::grid<openvdb::FloatGrid>(grid);
    EXPECT_TRUE(floats);
    return floats;
}

TEST(GridBuilder, KeepsHounsfieldUnitsFromSlopeAndIntercept) {
    // int16 CT: stored 0..4 with slope 2 and intercept -1024 gives -1024..-1016 HU.
    DenseVolume volume = makeVolume<std::int16_t>({5, 1, 1}, {0, 1, 2, 3, 4}, SampleType::Int16);
    volume.slope = 2.0;
    volume.intercept = -1024.0;
    auto grid = asFloat(buildGrid(volume, {}));
    EXPECT_EQ(grid->getName(), "density");
    auto accessor = grid->getConstAccessor();
    EXPECT_FALSE(accessor.isValueOn(openvdb::Coord(0, 0, 0)));  // the minimum is background
    for (int i = 1; i < 5; ++i) {
        EXPECT_TRUE(accessor.isValueOn(openvdb::Coord(i, 0, 0)));
        EXPECT_EQ(accessor.getValue(openvdb::Coord(i, 0, 0)), -1024.0f + 2.0f * i);
    }
    const auto metadata = readVolumeMetadata(*grid);
    ASSERT_TRUE(metadata);
    EXPECT_EQ(metadata->valueMin, -1024.0);
    EXPECT_EQ(metadata->valueMax, -1016.0);
    EXPECT_EQ(metadata->background, -1024.0);
    EXPECT_EQ(metadata->sourceType, "int16");
    EXPECT_EQ(metadata->rawSourceBytes(), 10u);
}

TEST(GridBuilder, ThresholdDeactivatesAtOrBelowAndBackgroundIsTheirMean) {
    DenseVolume volume = makeVolume<float>({4, 1, 1}, {-3000.f, -1000.f, -500.f, 40.f},
                                           SampleType::Float32);
    GridBuildSettings settings;
    settings.threshold = -500.0;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_EQ(grid->activeVoxelCount(), 1u);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(3, 0, 0)));
    EXPECT_FLOAT_EQ(grid->background(), -1500.0f);
    EXPECT_FLOAT_EQ(grid->tree().getValue(openvdb::Coord(0, 0, 0)), -1500.0f);
    EXPECT_EQ(readVolumeMetadata(*grid)->threshold, -500.0);
}

TEST(GridBuilder, RejectsNaNAndInfWithTheirCount) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    DenseVolume volume = makeVolume<float>({4, 1, 1}, {1.f, nan, inf, 2.f}, SampleType::Float32);
    GridBuildSettings settings;
    settings.sourceFile = "scan.nii";
    try {
        buildGrid(volume, settings);
        FAIL() << "NaN voxels were accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("scan.nii: 2 voxels are NaN or Inf"),
                  std::string::npos)
            << error.what();
    }
    settings.nanTo = 0.0f;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_FLOAT_EQ(grid->tree().getValue(openvdb::Coord(3, 0, 0)), 2.0f);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(1, 0, 0)));  // replaced by 0, the minimum
}

TEST(GridBuilder, ColourBecomesVec3ColorGridThresholdedOnLuminance) {
    DenseVolume volume = makeVolume<std::uint8_t>({2, 1, 1}, {0, 0, 10, 200, 100, 50},
                                                  SampleType::UInt8, 3);
    auto grid = openvdb::GridBase::grid<openvdb::Vec3SGrid>(buildGrid(volume, {}));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "color");
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(0, 0, 0)));
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 0, 0)), openvdb::Vec3s(200, 100, 50));
    EXPECT_EQ(grid->background(), openvdb::Vec3s(0, 0, 10));
    EXPECT_EQ(readVolumeMetadata(*grid)->channels, 3);
}

TEST(GridBuilder, TransformMapsIndexToWorldWithShearAndAnisotropicSpacing) {
    DenseVolume volume = makeVolume<std::uint8_t>({2, 2, 2}, {0, 1, 2, 3, 4, 5, 6, 7},
                                                  SampleType::UInt8);
    const double rows[3][4] = {{0.3, 0, 0, -10}, {0, 0.3, 0.15, 20}, {0, 0, 5.0, 30}};
    volume.worldFromIndex = worldFromIndexRows(rows);
    auto grid = buildGrid(volume, {});
    const openvdb::Vec3d world = grid->indexToWorld(openvdb::Vec3d(1, 1, 1));
    EXPECT_NEAR(world.x(), -9.7, 1e-12);
    EXPECT_NEAR(world.y(), 20.45, 1e-12);
    EXPECT_NEAR(world.z(), 35.0, 1e-12);
    EXPECT_FALSE(grid->transform().isLinear() && grid->transform().hasUniformScale());
    const auto metadata = readVolumeMetadata(*grid);
    EXPECT_NEAR(metadata->spacingMm.y(), 0.3, 1e-12);
    EXPECT_NEAR(metadata->spacingMm.z(), std::sqrt(0.15 * 0.15 + 25.0), 1e-12);
}

TEST(GridBuilder, RejectsADegenerateOrientation) {
    DenseVolume volume = makeVolume<std::uint8_t>({2, 1, 1}, {0, 1}, SampleType::UInt8);
    const double rows[3][4] = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0, 0, 1, 0}};
    volume.worldFromIndex = worldFromIndexRows(rows);
    EXPECT_THROW(buildGrid(volume, {}), InputError);
}

TEST(GridBuilder, LeafBordersAndPartialLeavesKeepEveryVoxel) {
    // 19 x 9 x 3 spans partial leaves on every axis.
    const std::array<std::int64_t, 3> dims{19, 9, 3};
    std::vector<std::uint16_t> values(19 * 9 * 3);
    for (std::size_t v = 0; v < values.size(); ++v) values[v] = std::uint16_t(v + 1);
    auto grid = asFloat(buildGrid(makeVolume(dims, values, SampleType::UInt16), {}));
    std::size_t v = 0;
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 9; ++j) {
            for (int i = 0; i < 19; ++i, ++v) {
                ASSERT_EQ(grid->tree().getValue(openvdb::Coord(i, j, k)), float(values[v]));
            }
        }
    }
    EXPECT_EQ(grid->activeVoxelCount(), values.size() - 1);
}

}  // namespace
}  // namespace gvr
