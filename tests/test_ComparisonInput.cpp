// What `gvr eval` compares: grids as dense samples with their data range, and
// single images in OpenImageIO's 0..1 scale, refused when they hold NaN or Inf.

#include "io/ComparisonInput.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdint>
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

}  // namespace
}  // namespace gvr
