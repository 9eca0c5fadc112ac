// Ingest as a whole: a raw volume to a grid in physical units with its source
// recorded, labels placed on it (and a warning when they miss it), a .vdb read back
// as it is, and the warning for a CT threshold that empties the lungs.

#include "io/Ingest.h"
#include "io/formats/GridFile.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace gvr {
namespace {

IngestOptions rawInt16(std::array<std::int64_t, 3> dims) {
    IngestOptions options;
    options.read.raw = RawLayout{dims, SampleType::Int16, 1, hostIsBigEndian(), 0};
    options.read.spacingMm = openvdb::Vec3d(1.0);
    return options;
}

float valueAt(const openvdb::GridBase& grid, const openvdb::Coord& ijk) {
    return static_cast<const openvdb::FloatGrid&>(grid).tree().getValue(ijk);
}

/// 4 x 3 x 2 Hounsfield-like values, negative ones among them, i fastest.
std::vector<std::int16_t> smallVolume() {
    std::vector<std::int16_t> values(24);
    for (std::size_t n = 0; n < values.size(); ++n) values[n] = std::int16_t(-1024 + 100 * int(n));
    return values;
}

TEST(Ingest, ARawVolumeBecomesAGridWithItsValuesAndItsSource) {
    test::TempDir dir;
    const std::string path = dir.path("scan.raw");
    test::writeBytes(path, test::rawBytes(smallVolume()));
    const IngestResult result = ingest(path, rawInt16({4, 3, 2}));
    ASSERT_TRUE(result.grid);
    EXPECT_EQ(result.grid->valueType(), "float");
    EXPECT_EQ(valueAt(*result.grid, openvdb::Coord(3, 2, 1)), float(-1024 + 100 * 23));
    EXPECT_EQ(valueAt(*result.grid, openvdb::Coord(1, 1, 0)), float(-1024 + 100 * 5));
    const std::optional<VolumeMetadata> metadata = readVolumeMetadata(*result.grid);
    ASSERT_TRUE(metadata);
    EXPECT_EQ(metadata->sourceFile, path);
    EXPECT_EQ(metadata->dims, openvdb::Vec3i(4, 3, 2));
    EXPECT_FALSE(result.labels);
}

/// Ingests @a values (a 2 x 2 x 2 raw volume of @a type) and checks every voxel:
/// kept exactly, or counted among the rounded ones, in the metadata and a warning.
template <typename T>
void expectIntegersKeptOrTheRoundedCounted(SampleType type, const std::vector<T>& values) {
    SCOPED_TRACE(sampleTypeName(type));
    test::TempDir dir;
    const std::string path = dir.path("counts.raw");
    test::writeBytes(path, test::rawBytes(values));
    IngestOptions options;
    options.read.raw = RawLayout{{2, 2, 2}, type, 1, hostIsBigEndian(), 0};
    const IngestResult result = ingest(path, options);
    std::uint64_t changed = 0;
    for (int n = 0; n < 8; ++n) {
        const double stored = double(valueAt(*result.grid, openvdb::Coord(n % 2, (n / 2) % 2, n / 4)));
        changed += stored == double(values[n]) ? 0 : 1;
        EXPECT_EQ(stored, double(float(values[n]))) << values[n];  // at worst the nearest float
    }
    EXPECT_EQ(readVolumeMetadata(*result.grid)->roundedVoxels, changed);
    const bool warned =
        !result.warnings.empty() &&
        result.warnings.back().find(" integers beyond 2^24, which the float32 grid rounds") != std::string::npos;
    EXPECT_EQ(warned, changed > 0);
    if (sizeof(T) <= 2) {
        EXPECT_EQ(changed, 0u);
    }
}

/// The type's lowest and highest values, those next to them, 0, 1, 2^24 and 2^24 + 1
/// where the type holds them.
template <typename T>
std::vector<T> edgesOf() {
    using Limits = std::numeric_limits<T>;
    const auto clamp = [](long long v) { return T(std::clamp<long long>(v, Limits::min(), Limits::max())); };
    return {Limits::min(),        T(Limits::min() + 1), T(0),         T(1), clamp(1 << 24),
            clamp((1 << 24) + 1), T(Limits::max() - 1), Limits::max()};
}

TEST(Ingest, IntegersOfEveryTypeAreKeptOrTheVoxelsFloatRoundsAreCountedAndWarned) {
    // 16777217 became 16777216 with exit 0 and no word: a label atlas was changed.
    expectIntegersKeptOrTheRoundedCounted(SampleType::UInt8, edgesOf<std::uint8_t>());
    expectIntegersKeptOrTheRoundedCounted(SampleType::Int8, edgesOf<std::int8_t>());
    expectIntegersKeptOrTheRoundedCounted(SampleType::UInt16, edgesOf<std::uint16_t>());
    expectIntegersKeptOrTheRoundedCounted(SampleType::Int16, edgesOf<std::int16_t>());
    expectIntegersKeptOrTheRoundedCounted(SampleType::UInt32, edgesOf<std::uint32_t>());
    expectIntegersKeptOrTheRoundedCounted(SampleType::Int32, edgesOf<std::int32_t>());
    expectIntegersKeptOrTheRoundedCounted<std::uint32_t>(SampleType::UInt32,
                                                         {4000000001u, 4000000000u, 16777217u, 3, 4, 5, 6, 7});
}

TEST(Ingest, LabelsArePlacedOnTheImageAndAWarningSaysWhenTheyMissIt) {
    test::TempDir dir;
    test::writeBytes(dir.path("scan.raw"), test::rawBytes(smallVolume()));
    std::vector<std::int16_t> labels(24, 0);
    labels[5] = 7;
    test::writeBytes(dir.path("labels.raw"), test::rawBytes(labels));
    IngestOptions options = rawInt16({4, 3, 2});
    options.labels = dir.path("labels.raw");
    const IngestResult placed = ingest(dir.path("scan.raw"), options);
    ASSERT_TRUE(placed.labels);
    EXPECT_EQ(placed.labels->activeVoxelCount(), 1u);
    EXPECT_EQ(placed.labels->tree().getValue(openvdb::Coord(1, 1, 0)), 7);
    EXPECT_TRUE(placed.warnings.empty());

    test::writeBytes(dir.path("labels.raw"), test::rawBytes(std::vector<std::int16_t>(24, 0)));
    const IngestResult missed = ingest(dir.path("scan.raw"), options);
    ASSERT_EQ(missed.warnings.size(), 1u);
    EXPECT_NE(missed.warnings[0].find("do not overlap the image"), std::string::npos) << missed.warnings[0];
}

TEST(Ingest, LoadOrIngestReadsAVdbAsItIsWithItsLabels) {
    test::TempDir dir;
    test::writeBytes(dir.path("scan.raw"), test::rawBytes(smallVolume()));
    std::vector<std::int16_t> labels(24, 0);
    labels[23] = 3;
    test::writeBytes(dir.path("labels.raw"), test::rawBytes(labels));
    IngestOptions options = rawInt16({4, 3, 2});
    options.labels = dir.path("labels.raw");
    const IngestResult ingested = ingest(dir.path("scan.raw"), options);
    writeGridFile(dir.path("scan.vdb"), {ingested.grid, ingested.labels});

    const IngestResult loaded = loadOrIngest(dir.path("scan.vdb"), {});
    ASSERT_TRUE(loaded.grid);
    ASSERT_TRUE(loaded.labels);
    EXPECT_EQ(valueAt(*loaded.grid, openvdb::Coord(3, 2, 1)), valueAt(*ingested.grid, openvdb::Coord(3, 2, 1)));
    EXPECT_EQ(loaded.labels->tree().getValue(openvdb::Coord(3, 2, 1)), 3);
}

/// A CT of a body (40 HU) in air (-1000 HU) with a lung (-890 HU) inside it.
std::vector<std::int16_t> chest(int side) {
    std::vector<std::int16_t> values(std::size_t(side) * side * side);
    const double centre = 0.5 * (side - 1);
    for (int k = 0; k < side; ++k) {
        for (int j = 0; j < side; ++j) {
            for (int i = 0; i < side; ++i) {
                const double r =
                    std::sqrt((i - centre) * (i - centre) + (j - centre) * (j - centre) + (k - centre) * (k - centre));
                values[(std::size_t(k) * side + j) * side + i] = r < 6.0 ? -890 : r < 10.0 ? 40 : -1000;
            }
        }
    }
    return values;
}

TEST(Ingest, ACtThresholdThatEmptiesTheLungsIsWarnedAndTheDefaultIsNot) {
    test::TempDir dir;
    constexpr int kSide = 24;
    test::writeBytes(dir.path("chest.raw"), test::rawBytes(chest(kSide)));
    IngestOptions options = rawInt16({kSide, kSide, kSide});
    options.build.modality = "CT";
    EXPECT_TRUE(ingest(dir.path("chest.raw"), options).warnings.empty()) << "-950 HU keeps the lung";
    options.build.threshold = -500.0;
    const IngestResult emptied = ingest(dir.path("chest.raw"), options);
    ASSERT_EQ(emptied.warnings.size(), 1u);
    EXPECT_NE(emptied.warnings[0].find("lungs are about -890 HU"), std::string::npos) << emptied.warnings[0];
}

TEST(Ingest, AMissingInputIsNamed) {
    test::TempDir dir;
    const std::string missing = dir.path("nowhere.nii.gz");
    const std::string message = test::errorMessageOf<InputError>([&] { ingest(missing, {}); });
    EXPECT_EQ(message.rfind(missing + ": ", 0), 0u) << message;
}

}  // namespace
}  // namespace gvr
