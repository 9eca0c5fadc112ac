// What `gvr eval` compares: grids as dense samples with their data range, and
// single images in OpenImageIO's 0..1 scale, refused when they hold NaN or Inf.

#include "io/formats/GridFile.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"
#include "workflow/ComparisonInput.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

namespace gvr {
namespace {

void writeGreyImage(const std::string& path, int width, int height, OIIO::TypeDesc type, const void* pixels) {
    auto output = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(output);
    ASSERT_TRUE(output->open(path, OIIO::ImageSpec(width, height, 1, type)));
    ASSERT_TRUE(output->write_image(type, pixels));
    output->close();
}

TEST(ComparisonInput, AnIngestedGridKeepsItsBoxAndRecordedRange) {
    const openvdb::GridBase::Ptr grid =
        test::makeGrid({4, 3, 2}, [](int i, int j, int k) { return float(1 + i + 10 * j + 100 * k); });
    const ComparisonInput input = comparisonInputOf(grid, "grid");
    EXPECT_FALSE(input.isImage);
    EXPECT_EQ(input.grid.get(), grid.get());
    EXPECT_EQ(input.volume.dims, openvdb::Coord(4, 3, 2));
    EXPECT_EQ(input.volume.channels, 1);
    EXPECT_EQ(input.volume.at(3, 2, 1)[0], 124.0f);
    EXPECT_EQ(input.volume.at(1, 2, 0)[0], 22.0f);
    EXPECT_EQ(input.dataRange, 123.0);  // 124 - 1, as ingest recorded it
}

TEST(ComparisonInput, AGridWithoutIngestMetadataUsesItsActiveBoxAndSampleRange) {
    const openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValue(openvdb::Coord(5, 5, 5), 2.0f);
    grid->tree().setValue(openvdb::Coord(6, 5, 5), 10.0f);
    const ComparisonInput input = comparisonInputOf(grid, "grid");
    EXPECT_EQ(input.volume.dims, openvdb::Coord(2, 1, 1));
    ASSERT_EQ(input.volume.values.size(), 2u);
    EXPECT_EQ(input.volume.values[0], 2.0f);
    EXPECT_EQ(input.volume.values[1], 10.0f);
    EXPECT_EQ(input.dataRange, 8.0);
}

TEST(ComparisonInput, AnIntegerGridIsRefused) {
    const openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    grid->tree().setValue(openvdb::Coord(0, 0, 0), 3);
    EXPECT_THROW(comparisonInputOf(grid, "grid"), InputError);
}

TEST(ComparisonInput, AnImageIsReadInTheZeroToOneScale) {
    test::TempDir dir;
    const std::string path = dir.path("slice.png");
    const std::vector<std::uint8_t> pixels = {0, 51, 102, 153, 204, 255};
    writeGreyImage(path, 3, 2, OIIO::TypeDesc::UINT8, pixels.data());
    const ComparisonInput input = loadComparisonInput(path, {});
    EXPECT_TRUE(input.isImage);
    EXPECT_FALSE(input.grid);
    EXPECT_EQ(input.volume.dims, openvdb::Coord(3, 2, 1));
    ASSERT_EQ(input.volume.values.size(), 6u);
    for (std::size_t n = 0; n < 6; ++n) EXPECT_NEAR(input.volume.values[n], 0.2 * n, 1e-6) << n;
    EXPECT_NEAR(input.dataRange, 1.0, 1e-6);
}

TEST(ComparisonInput, AnImageWithNanOrInfIsRefusedWithTheCount) {
    test::TempDir dir;
    const std::string path = dir.path("bad.exr");
    const std::vector<float> pixels = {1.0f, std::numeric_limits<float>::quiet_NaN(), 0.5f,
                                       std::numeric_limits<float>::infinity()};
    writeGreyImage(path, 4, 1, OIIO::TypeDesc::FLOAT, pixels.data());
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { loadComparisonInput(path, {}); }),
              path + ": 2 samples are NaN or Inf");
}

TEST(ComparisonInput, AMissingFileIsNamed) {
    test::TempDir dir;
    const std::string path = dir.path("none.vdb");
    const std::string message = test::errorMessageOf<InputError>([&] { loadComparisonInput(path, {}); });
    EXPECT_NE(message.find(path), std::string::npos) << message;
}

/// A DICOM series of the chest's first @a slices slices (padding -2000 stored, -3024 HU).
std::string chestSlices(const test::TempDir& dir, int slices) {
    const std::string folder = dir.path("chest");
    std::filesystem::create_directory(folder);
    for (int s = 1; s <= slices; ++s) {
        const std::string name = "1-" + std::string(s < 10 ? "00" : "0") + std::to_string(s) + ".dcm";
        std::filesystem::copy(test::sharedData("ct-chest-ricord-512/" + name), folder + "/" + name);
    }
    return folder;
}

// Compared with its thresholded grid, the chest's fit scored 35.47 dB; with the
// DICOM as decoded, 14.25 (30.9 over the body's range).
TEST(ComparisonInput, ASourceIsReadAsItIsWithOnlyItsMarkedPaddingLeftOut) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string folder = chestSlices(dir, 3);
    const ComparisonInput asRead = loadComparisonInput(folder, IngestOptions{});
    const IngestResult ingested = ingest(folder, IngestOptions{});
    const auto metadata = readVolumeMetadata(*ingested.grid);
    ASSERT_TRUE(metadata && metadata->markedPadding);
    EXPECT_EQ(*metadata->markedPadding, -3024.0);  // the stored -2000, rescaled by the intercept -1024
    ASSERT_GT(asRead.excludedVoxels, 0u);
    std::size_t air = 0, foreground = 0;
    float lowest = INFINITY, highest = -INFINITY;
    for (std::size_t n = 0; n < asRead.volume.voxelCount(); ++n) {
        const float value = asRead.volume.values[n];
        if (!asRead.excluded[n]) lowest = std::min(lowest, value), highest = std::max(highest, value);
        EXPECT_EQ(asRead.excluded[n] == 1, value == -3024.0f) << n;
        EXPECT_NE(value, float(metadata->background)) << "voxel " << n << " holds the grid's background";
        air += !asRead.excluded[n] && value <= -950.0f;
        foreground += asRead.volume.foreground[n];
    }
    EXPECT_GT(air, 0u);                                        // air the threshold drops, kept as it is
    EXPECT_EQ(foreground, ingested.grid->activeVoxelCount());  // what ingest keeps
    EXPECT_EQ(asRead.foregroundRule, "the voxels ingest keeps (above -950)");
    EXPECT_EQ(asRead.dataRange, double(highest) - double(lowest));  // over the voxels kept
    EXPECT_GT(lowest, -3024.0f);
    EXPECT_NE(
        asRead.readAs.find(std::to_string(asRead.excludedVoxels) + " voxels at -3024, which the file marks as padding"),
        std::string::npos)
        << asRead.readAs;
}

TEST(ComparisonInput, AGridIsComparedAsStoredAndSaysWhatItsThresholdLeft) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string folder = chestSlices(dir, 2);
    writeGridFile(dir.path("chest.vdb"), {ingest(folder, IngestOptions{}).grid});
    const ComparisonInput stored = loadComparisonInput(dir.path("chest.vdb"), IngestOptions{});
    EXPECT_TRUE(stored.excluded.empty());
    EXPECT_EQ(stored.readAs.rfind("the grid as stored: voxels at or below its threshold -950 hold its background ", 0),
              0u)
        << stored.readAs;
}

}  // namespace
}  // namespace gvr
