// What `gvr info` says about a grid: sizes, value range, metadata and affine, in
// JSON and as text, checked on small grids whose answers are known by hand.

#include "cli/GridSummary.h"
#include "io/DenseVolume.h"
#include "io/asset/AssetExport.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

namespace gvr {
namespace {

/// Two active voxels, -2.5 at (1, 2, 3) and 7 at (4, 2, 3), on voxels of 0.5 x 2 x 3 mm
/// moved by (10, 20, 30) mm, with three metadata values.
openvdb::FloatGrid::Ptr twoVoxelGrid() {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->tree().setValue(openvdb::Coord(1, 2, 3), -2.5f);
    grid->tree().setValue(openvdb::Coord(4, 2, 3), 7.0f);
    openvdb::math::Mat4d worldFromIndex = worldFromSpacing(openvdb::Vec3d(0.5, 2.0, 3.0));
    worldFromIndex.setTranslation(openvdb::Vec3d(10.0, 20.0, 30.0));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(worldFromIndex));
    grid->insertMeta("gvr_modality", openvdb::StringMetadata("CT"));
    grid->insertMeta("count", openvdb::Int32Metadata(7));
    grid->insertMeta("offset", openvdb::Vec3DMetadata(openvdb::Vec3d(1.0, 2.0, 3.0)));
    return grid;
}

TEST(GridSummary, ADccExportsSpacingIsGivenInMillimetresNotItsMetres) {
    openvdb::FloatGrid::Ptr grid = twoVoxelGrid();
    grid->setTransform(
        openvdb::math::Transform::createLinearTransform(worldFromSpacing(openvdb::Vec3d(0.5e-3, 2e-3, 3e-3))));
    grid->insertMeta("gvr_units", openvdb::StringMetadata(kDccUnits));
    const GridSummary s = summarizeGrid(*grid);
    EXPECT_DOUBLE_EQ(s.spacingMm.x(), 0.5);  // it printed "0.0005 x 0.002 x 0.003 mm"
    EXPECT_DOUBLE_EQ(s.spacingMm.z(), 3.0);
    EXPECT_NE(toText(s).find("spacing:       0.5 x 2 x 3 mm"), std::string::npos) << toText(s);
}

TEST(GridSummary, SizesRangeAndPlacementOfASmallGrid) {
    const GridSummary s = summarizeGrid(*twoVoxelGrid());
    EXPECT_EQ(s.name, "density");
    EXPECT_EQ(s.valueType, "float");
    EXPECT_EQ(s.gridClass, "fog volume");
    EXPECT_EQ(s.dims, openvdb::Coord(4, 1, 1));  // the active bounding box, not the tree's extent
    EXPECT_DOUBLE_EQ(s.spacingMm.x(), 0.5);
    EXPECT_DOUBLE_EQ(s.spacingMm.y(), 2.0);
    EXPECT_DOUBLE_EQ(s.spacingMm.z(), 3.0);
    EXPECT_EQ(s.valueMin, -2.5);
    EXPECT_EQ(s.valueMax, 7.0);
    EXPECT_EQ(s.activeVoxels, 2u);
    EXPECT_GT(s.memoryBytes, 0u);
    ASSERT_TRUE(s.affine);
    // The column form: world = affine * (i, j, k, 1).
    const auto& a = *s.affine;
    EXPECT_DOUBLE_EQ(a[0][0], 0.5);
    EXPECT_DOUBLE_EQ(a[1][1], 2.0);
    EXPECT_DOUBLE_EQ(a[2][2], 3.0);
    EXPECT_DOUBLE_EQ(a[0][3], 10.0);
    EXPECT_DOUBLE_EQ(a[1][3], 20.0);
    EXPECT_DOUBLE_EQ(a[2][3], 30.0);
    EXPECT_DOUBLE_EQ(a[3][0], 0.0);
    EXPECT_DOUBLE_EQ(a[3][3], 1.0);
}

TEST(GridSummary, MetadataIsTypedAndNameAndClassAreNotRepeated) {
    const GridSummary s = summarizeGrid(*twoVoxelGrid());
    EXPECT_EQ(s.metadata.size(), 3u) << s.metadata.dump();
    EXPECT_EQ(s.metadata.at("gvr_modality").get<std::string>(), "CT");
    EXPECT_TRUE(s.metadata.at("count").is_number_integer());
    EXPECT_EQ(s.metadata.at("count").get<int>(), 7);
    EXPECT_EQ(s.metadata.at("offset"), nlohmann::json::array({1.0, 2.0, 3.0}));
}

TEST(GridSummary, JsonCarriesEveryField) {
    const nlohmann::json j = toJson(summarizeGrid(*twoVoxelGrid()));
    EXPECT_EQ(j.at("name").get<std::string>(), "density");
    EXPECT_EQ(j.at("grid_class").get<std::string>(), "fog volume");
    EXPECT_EQ(j.at("dims"), nlohmann::json::array({4, 1, 1}));
    EXPECT_EQ(j.at("value_min").get<double>(), -2.5);
    EXPECT_EQ(j.at("value_max").get<double>(), 7.0);
    EXPECT_EQ(j.at("active_voxels").get<std::uint64_t>(), 2u);
    EXPECT_EQ(j.at("metadata").at("count").get<int>(), 7);
    EXPECT_DOUBLE_EQ(j.at("affine").at(1).at(3).get<double>(), 20.0);
}

TEST(GridSummary, TextNamesTheGridAndGivesTheShareOfTheBox) {
    const std::string text = toText(summarizeGrid(*twoVoxelGrid()));
    for (const char* line :
         {"grid 'density' (float, fog volume)\n", "  dimensions:    4 x 1 x 1 voxels (active bounding box)\n",
          "  spacing:       0.5 x 2 x 3 mm\n", "  value range:   -2.5 .. 7 (active voxels)\n",
          "  active voxels: 2 (50 % of the box)\n", "  metadata:\n", "    gvr_modality = CT\n", "    count = 7\n",
          "    offset = [1.0,2.0,3.0]\n"}) {
        EXPECT_NE(text.find(line), std::string::npos) << "missing: " << line << "in:\n" << text;
    }
}

TEST(GridSummary, AnEmptyGridHasNoRangeRatherThanInfinities) {
    const openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(5.0f);
    const GridSummary s = summarizeGrid(*grid);
    EXPECT_EQ(s.activeVoxels, 0u);
    EXPECT_EQ(s.valueMin, 0.0);
    EXPECT_EQ(s.valueMax, 0.0);
    EXPECT_TRUE(s.metadata.empty());
}

TEST(GridSummary, VectorRangesSpanEveryComponent) {
    const openvdb::Vec3SGrid::Ptr grid = openvdb::Vec3SGrid::create();
    grid->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(-1.0f, 5.0f, 2.0f));
    grid->tree().setValue(openvdb::Coord(3, 0, 0), openvdb::Vec3s(0.5f, 0.25f, 4.0f));
    const GridSummary s = summarizeGrid(*grid);
    EXPECT_EQ(s.valueType, "vec3s");
    EXPECT_EQ(s.valueMin, -1.0);
    EXPECT_EQ(s.valueMax, 5.0);
}

TEST(GridSummary, BytesAreFormattedForPeople) {
    EXPECT_EQ(formatBytes(0), "0 B");
    EXPECT_EQ(formatBytes(1023), "1023 B");
    EXPECT_EQ(formatBytes(1024), "1 KiB");
    EXPECT_EQ(formatBytes(1536), "1.5 KiB");
    EXPECT_EQ(formatBytes(std::uint64_t(5) << 20), "5 MiB");
    EXPECT_EQ(formatBytes(std::uint64_t(1) << 40), "1 TiB");
    // TiB is the largest unit: 2^64 bytes are 2^24 TiB.
    EXPECT_EQ(formatBytes(std::numeric_limits<std::uint64_t>::max()), "1.68e+07 TiB");
}

}  // namespace
}  // namespace gvr
