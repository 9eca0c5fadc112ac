// Structure labels beside the image: names read from AAL and FreeSurfer lists,
// the Int32 "labels" grid on the image's voxels (resampled only when asked), and
// label volumes that are not labels refused naming the file.

#include "io/LabelGrid.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace gvr {
namespace {

ReadOptions rawOptions(std::array<std::int64_t, 3> dims, SampleType type, openvdb::Vec3d spacing = openvdb::Vec3d(1.0),
                       int channels = 1) {
    ReadOptions options;
    options.raw = RawLayout{dims, type, channels, hostIsBigEndian(), 0};
    options.spacingMm = spacing;
    return options;
}

openvdb::GridBase::Ptr imageOf(std::array<int, 3> dims) {
    return test::makeGrid(dims, [](int i, int j, int k) { return float(1 + i + j + k); });
}

TEST(LabelGrid, NamesReadFromAalAndFreeSurferStyleLists) {
    test::TempDir dir;
    const std::string path = dir.path("names.txt");
    test::writeBytes(path,
                     "# AAL\n1 Precentral_L 2001\n\n2\tPrecentral_R  # right\n0 Unknown 0 0 0 0\n-3 Below 1 2 3\n");
    const LabelTable table = readLabelNames(path);
    // 0 is background, never a structure, even when the list names it.
    const std::map<int, std::string> expected{{-3, "Below"}, {1, "Precentral_L"}, {2, "Precentral_R"}};
    EXPECT_EQ(table.names, expected);
}

TEST(LabelGrid, NameListsThatAreNotIdNameLinesAreRefusedNamingTheLine) {
    test::TempDir dir;
    const std::string path = dir.path("names.txt");
    const auto errorFor = [&](const std::string& text) {
        test::writeBytes(path, text);
        return test::errorMessageOf<InputError>([&] { readLabelNames(path); });
    };
    EXPECT_EQ(errorFor("1 A\n2\n"), path + ": line 2 is not \"ID NAME ...\": 2");
    EXPECT_EQ(errorFor("x1 A\n"), path + ": line 1 is not \"ID NAME ...\": x1 A");
    EXPECT_EQ(errorFor("1.5 A\n"), path + ": line 1 is not \"ID NAME ...\": 1.5 A");
    EXPECT_EQ(errorFor("# nothing\n\n0 Background\n"), path + ": names no label");
    // An id past int32 would otherwise wrap onto another structure's id.
    EXPECT_EQ(errorFor("1 A\n4294967297 B\n"),
              path + ": line 2 names label 4294967297, beyond the 32-bit labels gvr keeps");
    // Latin-1 names were an internal error (invalid UTF-8) when the grid's JSON was written.
    EXPECT_EQ(errorFor("1 Thalamus\n2 Hippocampe_\xe9\n"), path + ": line 2 is not UTF-8 text");
    test::writeBytes(path, "1 Thalamus\n2 Hippocampe_\xc3\xa9\n");
    EXPECT_EQ(readLabelNames(path).names.at(2), "Hippocampe_\xc3\xa9");
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { readLabelNames(dir.path("missing.txt")); }),
              dir.path("missing.txt") + ": no such file");
}

TEST(LabelGrid, LabelsOnTheImagesLatticeKeepEverySixteenBitValueAndTheirNames) {
    test::TempDir dir;
    const std::string path = dir.path("labels.raw");
    const std::vector<std::int16_t> values{0, 5, 0, -32768, 7, 0, 0, 0, 5, 0, 0, 32767};
    test::writeBytes(path, test::rawBytes(values));
    const auto image = imageOf({3, 2, 2});
    LabelGridSettings settings;
    settings.names.names[5] = "Thalamus_L";
    settings.names.names[9] = "Absent";
    const openvdb::Int32Grid::Ptr labels =
        buildLabelGrid(path, rawOptions({3, 2, 2}, SampleType::Int16), *image, settings);
    EXPECT_EQ(labels->getName(), kLabelGridName);
    EXPECT_EQ(labels->transform(), image->transform());
    EXPECT_EQ(labels->activeVoxelCount(), 5u);  // 0 stays inactive
    EXPECT_EQ(labels->tree().getValue(openvdb::Coord(1, 0, 0)), 5);
    EXPECT_EQ(labels->tree().getValue(openvdb::Coord(0, 1, 0)), -32768);
    EXPECT_EQ(labels->tree().getValue(openvdb::Coord(1, 1, 0)), 7);
    EXPECT_EQ(labels->tree().getValue(openvdb::Coord(2, 0, 1)), 5);
    EXPECT_EQ(labels->tree().getValue(openvdb::Coord(2, 1, 1)), 32767);
    EXPECT_FALSE(labels->tree().isValueOn(openvdb::Coord(0, 0, 0)));
    // Only labels present are stored; unnamed ones get a made-up name.
    const std::map<int, std::string> expected{
        {-32768, "label_-32768"}, {5, "Thalamus_L"}, {7, "label_7"}, {32767, "label_32767"}};
    EXPECT_EQ(labelTableOf(*labels).names, expected);
}

TEST(LabelGrid, NonIntegerNaNAndManyChannelLabelsAreRefused) {
    test::TempDir dir;
    const std::string path = dir.path("labels.raw");
    const auto image = imageOf({2, 1, 1});
    const auto errorFor = [&](const std::vector<float>& values, int channels) {
        test::writeBytes(path, test::rawBytes(values));
        const ReadOptions options = rawOptions({2, 1, 1}, SampleType::Float32, openvdb::Vec3d(1.0), channels);
        return test::errorMessageOf<InputError>([&] { buildLabelGrid(path, options, *image, {}); });
    };
    const std::string half = errorFor({1.0f, 1.5f}, 1);
    EXPECT_EQ(half.rfind(path + ": is not a label volume: voxel 1 holds 1.5", 0), 0u) << half;
    const std::string nan = errorFor({std::numeric_limits<float>::quiet_NaN(), 1.0f}, 1);
    EXPECT_EQ(nan.rfind(path + ": is not a label volume: voxel 0 holds ", 0), 0u) << nan;
    EXPECT_NE(nan.find("not an integer"), std::string::npos) << nan;
    EXPECT_EQ(errorFor({1.0f, 2.0f, 3.0f, 1.0f, 2.0f, 3.0f}, 3),
              path + ": a label volume must have one channel, not 3");
}

TEST(LabelGrid, LabelsBeyondThirtyTwoBitsAreRefused) {
    test::TempDir dir;
    // Labels above the int32 range once read as "not an integer".
    std::string labels =
        "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_DOUBLE\nElementDataFile = LOCAL\n";
    for (double value : {0.0, 1.0, 3e9, 2.0, 0.0, 0.0, 0.0, 0.0})
        labels.append(reinterpret_cast<const char*>(&value), 8);
    test::writeBytes(dir.path("labels.mha"), labels);
    const auto image = test::makeGrid({2, 2, 2}, [](int, int, int) { return 1.0f; });
    const std::string hugeLabel =
        test::errorMessageOf<InputError>([&] { buildLabelGrid(dir.path("labels.mha"), {}, *image, {}); });
    EXPECT_NE(hugeLabel.find("beyond the 32-bit labels"), std::string::npos)
        << "a label of 3e9 gave: '" << hugeLabel << "'";
}

TEST(LabelGrid, TheLowestThirtyTwoBitLabelIsKept) {
    test::TempDir dir;
    std::string labels =
        "ObjectType = Image\nNDims = 3\nDimSize = 2 1 1\nElementType = MET_DOUBLE\nElementDataFile = LOCAL\n";
    for (double value : {-2147483648.0, 0.0}) labels.append(reinterpret_cast<const char*>(&value), 8);
    test::writeBytes(dir.path("labels.mha"), labels);
    const auto image = test::makeGrid({2, 1, 1}, [](int, int, int) { return 1.0f; });
    LabelGridSettings nearest;  // MetaImage's axes point the other way: placed by world position
    nearest.resample = true;
    const openvdb::Int32Grid::Ptr grid = buildLabelGrid(dir.path("labels.mha"), {}, *image, nearest);
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(0, 0, 0)), std::numeric_limits<std::int32_t>::min());
}

TEST(LabelGrid, ADifferentLatticeIsRefusedUnlessResampledToTheNearestLabel) {
    test::TempDir dir;
    const std::string path = dir.path("labels.raw");
    // 2 x 2 x 2 labels of 2 mm along x: 10 in the first column, 20 in the second.
    test::writeBytes(path, test::rawBytes(std::vector<std::int32_t>{10, 20, 10, 20, 10, 20, 10, 20}));
    const ReadOptions options = rawOptions({2, 2, 2}, SampleType::Int32, openvdb::Vec3d(2.0, 1.0, 1.0));
    const auto image = imageOf({4, 2, 2});
    const std::string refused = test::errorMessageOf<InputError>([&] { buildLabelGrid(path, options, *image, {}); });
    EXPECT_EQ(refused.rfind(path + ": is 2x2x2 voxels of ", 0), 0u) << refused;
    EXPECT_NE(refused.find("`resample_labels`"), std::string::npos) << refused;

    LabelGridSettings settings;
    settings.resample = true;
    const openvdb::Int32Grid::Ptr labels = buildLabelGrid(path, options, *image, settings);
    // Image voxel i lies at x = i mm, label voxel x / 2 rounded: 0, 1, 1, then past the labels' end.
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 2; ++j) {
            EXPECT_EQ(labels->tree().getValue(openvdb::Coord(0, j, k)), 10);
            EXPECT_EQ(labels->tree().getValue(openvdb::Coord(1, j, k)), 20);
            EXPECT_EQ(labels->tree().getValue(openvdb::Coord(2, j, k)), 20);
            EXPECT_FALSE(labels->tree().isValueOn(openvdb::Coord(3, j, k)));
        }
    }
    EXPECT_EQ(labels->activeVoxelCount(), 12u);
}

TEST(LabelGrid, AnImageNotFromIngestIsRefused) {
    test::TempDir dir;
    const std::string path = dir.path("labels.raw");
    test::writeBytes(path, test::rawBytes(std::vector<std::uint8_t>{1, 2}));
    const openvdb::FloatGrid::Ptr bare = openvdb::FloatGrid::create(0.0f);
    EXPECT_EQ(test::errorMessageOf<InputError>([&] {
                  buildLabelGrid(path, rawOptions({2, 1, 1}, SampleType::UInt8), *bare, {});
              }),
              path + ": labels need an image grid written by ingest");
}

TEST(LabelGrid, OnlyAnInt32GridNamedLabelsIsTheLabelGrid) {
    const openvdb::GridBase::Ptr image = imageOf({2, 2, 2});
    openvdb::FloatGrid::Ptr floatLabels = openvdb::FloatGrid::create(0.0f);
    floatLabels->setName(kLabelGridName);
    openvdb::Int32Grid::Ptr unnamed = openvdb::Int32Grid::create(0);
    openvdb::GridPtrVec grids{image, floatLabels, unnamed};
    EXPECT_FALSE(storedLabelGrid(grids));
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { findLabelGrid(grids, "scan.vdb"); }),
              "scan.vdb: holds no label grid; ingest the image with `labels=LABELS`");

    openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(0);
    labels->setName(kLabelGridName);
    grids.push_back(labels);
    EXPECT_EQ(storedLabelGrid(grids), labels);
    EXPECT_EQ(findLabelGrid(grids, "scan.vdb"), labels);
    EXPECT_TRUE(labelTableOf(*labels).names.empty());  // no names stored yet
}

}  // namespace
}  // namespace gvr
