#include "io/GridBuilder.h"
#include "io/formats/Readers.h"
#include "pipeline/Error.h"
#include "pipeline/Luminance.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <cmath>
#include <limits>
#include <random>

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

TEST(GridBuilder, ThresholdDeactivatesAtOrBelowAndBackgroundLeavesPaddingApart) {
    // -3024 is a scanner's padding: a third of the inactive voxels, left out of the
    // background, which is then air's own value, not an average of air and padding.
    DenseVolume volume = makeVolume<float>({4, 1, 1}, {-3024.f, -1000.f, -990.f, 40.f}, SampleType::Float32);
    GridBuildSettings settings;
    settings.threshold = -500.0;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_EQ(grid->activeVoxelCount(), 1u);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(3, 0, 0)));
    EXPECT_FLOAT_EQ(grid->background(), -995.0f);
    EXPECT_FLOAT_EQ(grid->tree().getValue(openvdb::Coord(0, 0, 0)), -995.0f);
    const VolumeMetadata metadata = *readVolumeMetadata(*grid);
    EXPECT_EQ(metadata.threshold, -500.0);
    EXPECT_EQ(metadata.padding, -3024.0);
    EXPECT_EQ(metadata.paddingVoxels, 1u);
}

TEST(GridBuilder, ARareLowestValueIsNoPaddingAndTheBackgroundIsTheMean) {
    std::vector<float> values(41, -1000.0f);
    values[0] = -3024.0f;  // one voxel in 40 inactive ones: under 5 %, noise rather than padding
    values[40] = 100.0f;
    DenseVolume volume = makeVolume<float>({41, 1, 1}, values, SampleType::Float32);
    GridBuildSettings settings;
    settings.threshold = -500.0;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_FLOAT_EQ(grid->background(), (-3024.0f - 39 * 1000.0f) / 40.0f);
    EXPECT_FALSE(readVolumeMetadata(*grid)->padding);
}

TEST(GridBuilder, ACtWithoutAThresholdLosesItsAirAndKeepsItsLungs) {
    DenseVolume volume = makeVolume<float>({3, 1, 1}, {-1000.f, -890.f, 40.f}, SampleType::Float32);
    volume.modality = "CT";
    auto grid = asFloat(buildGrid(volume, {}));
    EXPECT_EQ(readVolumeMetadata(*grid)->threshold, kCtDefaultThreshold);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(0, 0, 0)));
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(1, 0, 0)));
    volume.modality = "MR";  // other data keep everything above their minimum
    EXPECT_FALSE(readVolumeMetadata(*buildGrid(volume, {}))->threshold);
}

TEST(GridBuilder, ABrightBackgroundIsCutFromAbove) {
    // A specimen (dark) on white paper: the paper goes, and is what inactive voxels hold.
    DenseVolume volume = makeVolume<std::uint8_t>({4, 1, 1}, {250, 240, 90, 255}, SampleType::UInt8);
    GridBuildSettings settings;
    settings.thresholdAbove = 230.0;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_EQ(grid->activeVoxelCount(), 1u);
    EXPECT_TRUE(grid->tree().isValueOn(openvdb::Coord(2, 0, 0)));
    EXPECT_EQ(readVolumeMetadata(*grid)->thresholdAbove, 230.0);
    EXPECT_GT(grid->background(), 230.0f);
}

TEST(GridBuilder, FlippedAxesMirrorTheDataInTheWorld) {
    DenseVolume volume = makeVolume<std::uint8_t>({3, 2, 1}, {1, 2, 3, 4, 5, 6}, SampleType::UInt8);
    volume.worldFromIndex = worldFromSpacing(openvdb::Vec3d(0.5, 2.0, 1.0));
    const auto plain = asFloat(buildGrid(volume, {}));
    GridBuildSettings settings;
    settings.flip = {true, true, false};
    const auto flipped = asFloat(buildGrid(volume, settings));
    // The sample at index (i, j) now stands where (2 - i, 1 - j) stood: the volume is mirrored in place.
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 3; ++i) {
            const openvdb::Vec3d there = flipped->indexToWorld(openvdb::Coord(i, j, 0));
            EXPECT_TRUE(there.eq(plain->indexToWorld(openvdb::Coord(2 - i, 1 - j, 0)))) << i << "," << j;
        }
    }
    EXPECT_EQ(readVolumeMetadata(*flipped)->spacingMm, openvdb::Vec3d(0.5, 2.0, 1.0));
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
        EXPECT_NE(std::string(error.what()).find("scan.nii: 2 voxels are NaN or Inf"), std::string::npos)
            << error.what();
    }
    settings.nanTo = 0.0f;
    auto grid = asFloat(buildGrid(volume, settings));
    EXPECT_FLOAT_EQ(grid->tree().getValue(openvdb::Coord(3, 0, 0)), 2.0f);
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(1, 0, 0)));  // replaced by 0, the minimum
}

TEST(GridBuilder, ColourBecomesVec3ColorGridThresholdedOnLuminance) {
    DenseVolume volume = makeVolume<std::uint8_t>({2, 1, 1}, {0, 0, 10, 200, 100, 50}, SampleType::UInt8, 3);
    auto grid = openvdb::GridBase::grid<openvdb::Vec3SGrid>(buildGrid(volume, {}));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "color");
    EXPECT_FALSE(grid->tree().isValueOn(openvdb::Coord(0, 0, 0)));
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 0, 0)), openvdb::Vec3s(200, 100, 50));
    EXPECT_EQ(grid->background(), openvdb::Vec3s(0, 0, 10));
    EXPECT_EQ(readVolumeMetadata(*grid)->channels, 3);
}

TEST(GridBuilder, AColourSectionOnPaperKeepsItsRareDarkestVoxelAndThePaperIsOutside) {
    // White paper, a specimen in the middle whose darkest voxel is one of 2,000.
    const std::array<std::int64_t, 3> dims{20, 20, 5};
    std::vector<std::uint8_t> rgb;
    for (int k = 0; k < 5; ++k) {
        for (int j = 0; j < 20; ++j) {
            for (int i = 0; i < 20; ++i) {
                const bool specimen = std::abs(i - 10) < 4 && std::abs(j - 10) < 4 && k > 0 && k < 4;
                const bool darkest = i == 10 && j == 10 && k == 2;
                const std::uint8_t r = darkest ? 20 : specimen ? 120 + i : 250, g = specimen ? 60 + j : 248;
                rgb.insert(rgb.end(), {darkest ? std::uint8_t(20) : r, darkest ? std::uint8_t(5) : g,
                                       specimen ? std::uint8_t(40) : std::uint8_t(245)});
            }
        }
    }
    auto grid = openvdb::GridBase::grid<openvdb::Vec3SGrid>(buildGrid(makeVolume(dims, rgb, SampleType::UInt8, 3), {}));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->activeVoxelCount(), 20u * 20u * 5u);  // the darkest voxel is the specimen's, not background
    EXPECT_EQ(grid->tree().getValue(openvdb::Coord(10, 10, 2)), openvdb::Vec3s(20, 5, 40));
    // Outside the volume lies what its faces show, so that the paper does not fade
    // into a dark shell at the faces.
    EXPECT_EQ(grid->background(), openvdb::Vec3s(250, 248, 245));
    EXPECT_NEAR(readVolumeMetadata(*grid)->background, luminance(openvdb::Vec3d(250, 248, 245)), 1e-3);
    EXPECT_FALSE(readVolumeMetadata(*grid)->threshold);
}

TEST(GridBuilder, TransformMapsIndexToWorldWithShearAndAnisotropicSpacing) {
    DenseVolume volume = makeVolume<std::uint8_t>({2, 2, 2}, {0, 1, 2, 3, 4, 5, 6, 7}, SampleType::UInt8);
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

// Streamed builds: one slab of slices at a time must give the grid that the whole
// volume gives, voxel for voxel.

/// Every active voxel, value and the background agree, and so does the metadata.
template <typename GridT>
void expectSameGrids(const openvdb::GridBase::Ptr& wholeBase, const openvdb::GridBase::Ptr& streamedBase) {
    const auto whole = openvdb::GridBase::grid<GridT>(wholeBase);
    const auto streamed = openvdb::GridBase::grid<GridT>(streamedBase);
    ASSERT_TRUE(whole && streamed);
    EXPECT_EQ(streamed->activeVoxelCount(), whole->activeVoxelCount());
    EXPECT_EQ(streamed->background(), whole->background());
    auto accessor = streamed->getConstAccessor();
    for (auto voxel = whole->cbeginValueOn(); voxel; ++voxel) {
        ASSERT_TRUE(accessor.isValueOn(voxel.getCoord())) << voxel.getCoord();
        ASSERT_EQ(accessor.getValue(voxel.getCoord()), *voxel) << voxel.getCoord();
    }
    for (auto leaf = streamed->tree().cbeginLeaf(); leaf; ++leaf) {
        for (auto off = leaf->cbeginValueOff(); off; ++off) ASSERT_EQ(*off, streamed->background());
    }
    const VolumeMetadata a = *readVolumeMetadata(*whole), b = *readVolumeMetadata(*streamed);
    EXPECT_EQ(b.valueMin, a.valueMin);
    EXPECT_EQ(b.valueMax, a.valueMax);
    EXPECT_EQ(b.background, a.background);
    EXPECT_EQ(b.dims, a.dims);
    EXPECT_EQ(b.sourceType, a.sourceType);
}

/// Both builds of @a input: whole, and streamed in slabs of one leaf (8 slices).
std::pair<openvdb::GridBase::Ptr, openvdb::GridBase::Ptr> wholeAndStreamed(const std::string& input,
                                                                           const ReadOptions& read,
                                                                           GridBuildSettings settings) {
    const openvdb::GridBase::Ptr whole = buildGrid(readVolume(input, read), settings);
    settings.slabBytes = 1;
    const auto source = openSliceSource(input, read);
    EXPECT_TRUE(source);
    return {whole, buildGrid(*source, settings)};
}

TEST(GridBuilder, AStreamedBuildEqualsTheWholeBuildAlsoWhenTheMinimumComesLast) {
    // 21 x 13 x 37 int16 HU: five slabs, partial leaves on every axis. Slab 0 holds
    // -2000 and only the last slab the volume's minimum, -3024, so slab 0 is cut at
    // -2000 at first and must be built again at -3024.
    test::TempDir dir;
    const std::array<std::int64_t, 3> dims{21, 13, 37};
    std::vector<std::int16_t> values(std::size_t(dims[0] * dims[1] * dims[2]));
    std::mt19937 random(7);
    std::uniform_int_distribution<int> hu(-1000, 3000);
    for (auto& v : values) v = std::int16_t(hu(random));
    values[5] = -2000;
    values[values.size() - 3] = -3024;
    test::writeBytes(dir.path("ct.raw"), std::string(reinterpret_cast<const char*>(values.data()), values.size() * 2));
    ReadOptions read;
    read.raw = RawLayout{dims, SampleType::Int16, 1, false, 0};
    read.spacingMm = openvdb::Vec3d(0.7, 0.7, 1.25);

    for (const std::optional<double> threshold : {std::optional<double>(), std::optional<double>(100.0)}) {
        GridBuildSettings settings;
        settings.threshold = threshold;
        const auto [whole, streamed] = wholeAndStreamed(dir.path("ct.raw"), read, settings);
        expectSameGrids<openvdb::FloatGrid>(whole, streamed);
        if (!threshold) {
            EXPECT_TRUE(asFloat(streamed)->tree().isValueOn(openvdb::Coord(5, 0, 0)));
        }
    }
}

TEST(GridBuilder, AStreamedColourStackEqualsTheWholeStack) {
    GVR_REQUIRE_SHARED_DATA();
    const auto [whole, streamed] =
        wholeAndStreamed(test::sharedData("rgb-brainmaps54-cryosection"), {}, GridBuildSettings{});
    expectSameGrids<openvdb::Vec3SGrid>(whole, streamed);
}

TEST(GridBuilder, AStreamedDicomSeriesEqualsTheWholeSeries) {
    GVR_REQUIRE_SHARED_DATA();
    GridBuildSettings settings;
    settings.threshold = -500.0;
    const auto [whole, streamed] = wholeAndStreamed(test::sharedData("ct-chest-ricord-512"), {}, settings);
    expectSameGrids<openvdb::FloatGrid>(whole, streamed);
}

TEST(GridBuilder, AStreamedBuildCountsNonFiniteVoxelsInEverySlab) {
    test::TempDir dir;
    std::vector<float> values(4 * 4 * 20, 1.0f);
    values[3] = std::nanf("");
    values[values.size() - 1] = INFINITY;
    test::writeBytes(dir.path("v.raw"), std::string(reinterpret_cast<const char*>(values.data()), values.size() * 4));
    ReadOptions read;
    read.raw = RawLayout{{4, 4, 20}, SampleType::Float32, 1, false, 0};
    GridBuildSettings settings;
    settings.slabBytes = 1;
    try {
        buildGrid(*openSliceSource(dir.path("v.raw"), read), settings);
        ADD_FAILURE() << "NaN and Inf were accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("2 voxels are NaN or Inf"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace gvr
