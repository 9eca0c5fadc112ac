// What ingest records on a grid must come back field for field, absent optionals
// must stay absent, and the helpers on placement matrices must measure what they say.

#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstdint>

namespace gvr {
namespace {

VolumeMetadata everyField() {
    VolumeMetadata m;
    m.sourceFile = "ct/scan.nii.gz";
    m.modality = "CT";
    m.sourceType = "int16";
    m.channels = 1;
    m.dims = openvdb::Vec3i(512, 512, 301);
    m.spacingMm = openvdb::Vec3d(0.7, 0.7, 1.25);
    m.valueMin = -3024.0;
    m.valueMax = 3071.0;
    m.background = -1000.0;
    m.padding = -3024.0;
    m.paddingVoxels = 5'000'000'000ull;  // beyond 32 bits
    m.threshold = -500.0;
    m.thresholdAbove = 2000.0;
    m.storedSlope = 0.5;
    m.storedIntercept = -1024.0;
    m.niftiCodes = NiftiCodes{1, 4, 10};
    return m;
}

TEST(VolumeMetadata, EveryFieldRoundTrips) {
    openvdb::initialize();
    const openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    const VolumeMetadata m = everyField();
    writeVolumeMetadata(m, *grid);
    const std::optional<VolumeMetadata> back = readVolumeMetadata(*grid);
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(back->sourceFile, m.sourceFile);
    EXPECT_EQ(back->modality, "CT");
    EXPECT_EQ(back->sourceType, "int16");
    EXPECT_EQ(back->channels, 1);
    EXPECT_EQ(back->dims, m.dims);
    EXPECT_EQ(back->spacingMm, m.spacingMm);
    EXPECT_EQ(back->valueMin, -3024.0);
    EXPECT_EQ(back->valueMax, 3071.0);
    EXPECT_EQ(back->background, -1000.0);
    ASSERT_TRUE(back->padding.has_value());
    EXPECT_EQ(*back->padding, -3024.0);
    EXPECT_EQ(back->paddingVoxels, 5'000'000'000ull);
    ASSERT_TRUE(back->threshold.has_value());
    EXPECT_EQ(*back->threshold, -500.0);
    ASSERT_TRUE(back->thresholdAbove.has_value());
    EXPECT_EQ(*back->thresholdAbove, 2000.0);
    EXPECT_EQ(back->storedSlope, 0.5);
    EXPECT_EQ(back->storedIntercept, -1024.0);
    ASSERT_TRUE(back->niftiCodes.has_value());
    EXPECT_EQ(back->niftiCodes->sform, 1);
    EXPECT_EQ(back->niftiCodes->qform, 4);
    EXPECT_EQ(back->niftiCodes->xyztUnits, 10);
}

TEST(VolumeMetadata, AbsentOptionalsStayAbsent) {
    openvdb::initialize();
    const openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    VolumeMetadata m;
    m.sourceType = "uint8";
    m.dims = openvdb::Vec3i(4, 5, 6);
    writeVolumeMetadata(m, *grid);
    const std::optional<VolumeMetadata> back = readVolumeMetadata(*grid);
    ASSERT_TRUE(back.has_value());
    EXPECT_FALSE(back->padding.has_value());
    EXPECT_EQ(back->paddingVoxels, 0u);
    EXPECT_FALSE(back->threshold.has_value());
    EXPECT_FALSE(back->thresholdAbove.has_value());
    EXPECT_FALSE(back->niftiCodes.has_value());
    EXPECT_EQ(back->modality, "unknown");
    EXPECT_EQ(back->storedSlope, 1.0);
}

TEST(VolumeMetadata, AGridGvrDidNotIngestHasNone) {
    openvdb::initialize();
    const openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    EXPECT_FALSE(readVolumeMetadata(*grid).has_value());
    // Dims alone are not enough: the source type is needed to size the source.
    grid->insertMeta("gvr_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(2, 2, 2)));
    EXPECT_FALSE(readVolumeMetadata(*grid).has_value());
    grid->insertMeta("gvr_source_type", openvdb::StringMetadata("float32"));
    const std::optional<VolumeMetadata> back = readVolumeMetadata(*grid);
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(back->spacingMm, openvdb::Vec3d(1.0));
    EXPECT_EQ(back->channels, 1);
}

TEST(VolumeMetadata, RawSourceBytes) {
    VolumeMetadata m;
    m.sourceType = "uint16";
    m.channels = 3;
    m.dims = openvdb::Vec3i(10, 20, 3);
    EXPECT_EQ(m.rawSourceBytes(), 10u * 20u * 3u * 3u * 2u);
    // 4000^3 voxels overflow 32 bits.
    m.sourceType = "float64";
    m.channels = 1;
    m.dims = openvdb::Vec3i(4000, 4000, 4000);
    EXPECT_EQ(m.rawSourceBytes(), std::uint64_t(4000) * 4000 * 4000 * 8);
}

TEST(VolumeMetadata, RawSourceBytesOfAnUnknownTypeThrows) {
    VolumeMetadata m;
    m.sourceFile = "odd.raw";
    m.sourceType = "complex64";
    m.dims = openvdb::Vec3i(1, 1, 1);
    EXPECT_THROW(m.rawSourceBytes(), InputError);
}

TEST(VolumeMetadata, AxisSpacingIsTheLengthOfEachRow) {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m(0, 0) = 3.0;
    m(0, 1) = 4.0;  // a sheared or rotated axis: its length, not its x component
    m(1, 1) = 0.5;
    m(2, 2) = -2.0;  // a flipped axis still has a positive spacing
    m.setTranslation(openvdb::Vec3d(100.0, -50.0, 7.0));
    const openvdb::Vec3d spacing = axisSpacing(m);
    EXPECT_DOUBLE_EQ(spacing[0], 5.0);
    EXPECT_DOUBLE_EQ(spacing[1], 0.5);
    EXPECT_DOUBLE_EQ(spacing[2], 2.0);
}

TEST(VolumeMetadata, SamePlacementWithinTolerance) {
    const openvdb::math::Mat4d a = openvdb::math::Mat4d::identity();
    openvdb::math::Mat4d b = a;
    b.setTranslation(openvdb::Vec3d(0.0005, 0.0, 0.0));
    EXPECT_TRUE(samePlacement(a, b, 1e-3));
    b.setTranslation(openvdb::Vec3d(0.01, 0.0, 0.0));
    EXPECT_FALSE(samePlacement(a, b, 1e-3));
    // Sub-millimetre voxels: the tolerance floor of 1 mm keeps it absolute.
    openvdb::math::Mat4d fine = openvdb::math::Mat4d::identity();
    fine(0, 0) = fine(1, 1) = fine(2, 2) = 0.01;
    openvdb::math::Mat4d shifted = fine;
    shifted.setTranslation(openvdb::Vec3d(0.0, 0.0, 0.002));
    EXPECT_FALSE(samePlacement(fine, shifted, 1e-3));
    shifted.setTranslation(openvdb::Vec3d(0.0, 0.0, 0.0009));
    EXPECT_TRUE(samePlacement(fine, shifted, 1e-3));
    // A matrix with NaN places nothing, not even where it equals itself.
    openvdb::math::Mat4d broken = a;
    broken(1, 1) = std::nan("");
    EXPECT_FALSE(samePlacement(broken, broken, 1e-3));
    EXPECT_FALSE(samePlacement(a, broken, 1e-3));
}

}  // namespace
}  // namespace gvr
