// A decoded volume: its sizes, the affine conversions every reader relies on, and
// the memory check before a header's dimensions are trusted with an allocation.

#include "io/DenseVolume.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

namespace gvr {
namespace {

TEST(DenseVolume, SizesCountVoxelsChannelsAndBytesPerSample) {
    DenseVolume volume;
    EXPECT_EQ(volume.voxelCount(), 0u);
    volume.dims = {3, 4, 5};
    volume.channels = 3;
    volume.type = SampleType::Int16;
    EXPECT_EQ(volume.voxelCount(), 60u);
    EXPECT_EQ(volume.sampleBytes(), 360u);
    // 2^60 voxels must not wrap in the 64-bit count.
    volume.dims = {std::int64_t(1) << 20, std::int64_t(1) << 20, std::int64_t(1) << 20};
    EXPECT_EQ(volume.voxelCount(), std::uint64_t(1) << 60);
}

TEST(DenseVolume, TypedAccessKeepsNegativeSixteenBitValues) {
    const DenseVolume volume = test::makeVolume<std::int16_t>({3, 1, 1}, {-32768, -1, 32767}, SampleType::Int16);
    ASSERT_EQ(volume.samples.size(), 6u);
    EXPECT_EQ(volume.data<std::int16_t>()[0], -32768);
    EXPECT_EQ(volume.data<std::int16_t>()[1], -1);
    EXPECT_EQ(volume.data<std::int16_t>()[2], 32767);
}

TEST(DenseVolume, RowsAreReadAsWorldEqualsRowsTimesIndex) {
    const double rows[3][4] = {{1, 2, 3, 10}, {4, 5, 6, 20}, {7, 8, 9, 30}};
    const openvdb::math::Mat4d m = worldFromIndexRows(rows);
    // OpenVDB multiplies row vectors, so the matrix is the transpose of the rows.
    EXPECT_EQ(m.transform(openvdb::Vec3d(0, 0, 0)), openvdb::Vec3d(10, 20, 30));
    EXPECT_EQ(m.transform(openvdb::Vec3d(1, 0, 0)), openvdb::Vec3d(11, 24, 37));
    EXPECT_EQ(m.transform(openvdb::Vec3d(0, 2, 0)), openvdb::Vec3d(14, 30, 46));
    EXPECT_EQ(m.transform(openvdb::Vec3d(1, 1, 1)), openvdb::Vec3d(16, 35, 54));
    EXPECT_EQ(m(3, 3), 1.0);
    EXPECT_EQ(m(0, 3), 0.0);
}

TEST(DenseVolume, SpacingScalesEachAxisFromTheOrigin) {
    const openvdb::math::Mat4d m = worldFromSpacing(openvdb::Vec3d(0.5, 2.0, 3.0));
    EXPECT_EQ(m.transform(openvdb::Vec3d(0, 0, 0)), openvdb::Vec3d(0, 0, 0));
    EXPECT_EQ(m.transform(openvdb::Vec3d(2, 3, 4)), openvdb::Vec3d(1, 6, 12));
}

TEST(DenseVolume, AllocateSizesAndZeroesReserveLeavesEmpty) {
    DenseVolume volume;
    volume.dims = {3, 4, 5};
    volume.channels = 3;
    volume.type = SampleType::Int16;
    allocateSamples(volume, "v.nii");
    ASSERT_EQ(volume.samples.size(), 360u);
    EXPECT_TRUE(std::all_of(volume.samples.begin(), volume.samples.end(), [](unsigned char b) { return b == 0; }));
    // A reader appends what the file holds: nothing is there yet, but the room is.
    reserveSamples(volume, "v.nii");
    EXPECT_TRUE(volume.samples.empty());
    EXPECT_GE(volume.samples.capacity(), 360u);
}

TEST(DenseVolume, AbsurdHeaderDimensionsAreRefusedBeforeAnyAllocation) {
    const std::int64_t huge = std::int64_t(1) << 30;
    for (const std::array<std::int64_t, 3>& dims :
         {std::array<std::int64_t, 3>{huge, huge, huge}, std::array<std::int64_t, 3>{0, 4, 4},
          std::array<std::int64_t, 3>{-1, 4, 4}}) {
        DenseVolume volume;
        volume.dims = dims;
        volume.type = SampleType::Float64;
        const std::string allocated = test::errorMessageOf<InputError>([&] { allocateSamples(volume, "forged.nii"); });
        EXPECT_EQ(allocated.rfind("forged.nii: ", 0), 0u) << allocated;
        const std::string reserved = test::errorMessageOf<InputError>([&] { reserveSamples(volume, "forged.nii"); });
        EXPECT_EQ(reserved.rfind("forged.nii: ", 0), 0u) << reserved;
        EXPECT_EQ(volume.samples.capacity(), 0u);
    }
}

}  // namespace
}  // namespace gvr
