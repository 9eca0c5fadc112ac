// The NIfTI writer: values, geometry, datatype and codes survive a round trip
// through gvr's own reader; what cannot be stored is clamped and counted.

#include "io/formats/NiftiWriter.h"
#include "io/formats/Readers.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <nifti2_io.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

namespace gvr {
namespace {

/// Anisotropic, sheared and translated: the qform alone cannot hold it.
openvdb::math::Mat4d obliqueWorldFromIndex() {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m.setToScale(openvdb::Vec3d(0.5, 0.5, 3.0));
    m(0, 1) = 0.1;
    m.setTranslation(openvdb::Vec3d(-5.0, 2.0, 30.0));
    return m;
}

TEST(NiftiWriter, RoundTripsValuesAndAnObliqueAffine) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(5, 4, 3), 1);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = float(n) * 1.5f - 20.0f;
    volume.worldFromIndex = obliqueWorldFromIndex();
    const std::string path = dir.path("out.nii.gz");
    writeNifti(path, volume);
    const DenseVolume back = readNifti(path, ReadOptions{});
    ASSERT_EQ(back.dims, (std::array<std::int64_t, 3>{5, 4, 3}));
    ASSERT_EQ(back.type, SampleType::Float32);
    for (std::size_t n = 0; n < volume.values.size(); ++n) ASSERT_EQ(back.data<float>()[n], volume.values[n]);
    EXPECT_TRUE(back.worldFromIndex.eq(volume.worldFromIndex, 1e-6));
    // Only the file itself is left in the folder: no temporary.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.root()), {}), 1);
}

TEST(NiftiWriter, RgbBecomesRgb24) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(3, 2, 2), 3);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = float(n * 23) - 10.0f;
    writeNifti(dir.path("rgb.nii"), volume);
    const DenseVolume back = readNifti(dir.path("rgb.nii"), ReadOptions{});
    ASSERT_EQ(back.channels, 3);
    for (std::size_t n = 0; n < volume.values.size(); ++n) {
        ASSERT_EQ(back.data<std::uint8_t>()[n], std::clamp(std::lround(volume.values[n]), 0L, 255L));
    }
}

TEST(NiftiWriter, KeepsTheSourcesDatatypeScalingAndCodes) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(4, 3, 2), 1);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = -1024.0f + float(n) * 50.3f;
    volume.values[0] = -3000.0f;  // below what uint8 with this scaling holds
    volume.values[1] = 5000.0f;   // above it
    NiftiStorage storage;
    storage.type = SampleType::UInt8;
    storage.slope = 7.1;
    storage.intercept = -1024.0;
    storage.codes = NiftiCodes{2, 2, NIFTI_UNITS_MM | NIFTI_UNITS_SEC};
    const std::string path = dir.path("out.nii.gz");
    EXPECT_EQ(writeNifti(path, volume, storage), 2u);

    const DenseVolume back = readNifti(path, ReadOptions{});
    ASSERT_EQ(back.type, SampleType::UInt8);
    EXPECT_NEAR(back.slope, 7.1, 1e-6);
    EXPECT_EQ(back.intercept, -1024.0);
    ASSERT_TRUE(back.niftiCodes);
    EXPECT_EQ(back.niftiCodes->sform, 2);
    EXPECT_EQ(back.niftiCodes->qform, 2);
    EXPECT_EQ(back.niftiCodes->xyztUnits, NIFTI_UNITS_MM | NIFTI_UNITS_SEC);
    EXPECT_EQ(back.data<std::uint8_t>()[0], 0);
    EXPECT_EQ(back.data<std::uint8_t>()[1], 255);
    for (std::size_t n = 2; n < volume.values.size(); ++n) {
        const double physical = back.slope * back.data<std::uint8_t>()[n] + back.intercept;
        ASSERT_LE(std::abs(physical - volume.values[n]), 7.1 / 2 + 1e-3) << n;
    }
}

TEST(NiftiWriter, StorageFollowsTheSourceOrSaysWhyItIsFloat32) {
    VolumeMetadata source;
    source.sourceType = "int16";
    source.storedSlope = 0.5;
    source.storedIntercept = -10.0;
    source.niftiCodes = NiftiCodes{4, 0, 10};
    const NiftiStorage kept = niftiStorageLike(source, false);
    EXPECT_EQ(kept.type, SampleType::Int16);
    EXPECT_EQ(kept.slope, 0.5);
    EXPECT_EQ(kept.intercept, -10.0);
    EXPECT_EQ(kept.codes.sform, 4);
    EXPECT_EQ(kept.codes.qform, 0);
    EXPECT_TRUE(kept.float32Reason.empty());

    const NiftiStorage asked = niftiStorageLike(source, true);
    EXPECT_EQ(asked.type, SampleType::Float32);
    EXPECT_EQ(asked.slope, 1.0);
    EXPECT_EQ(asked.codes.sform, 4);  // the codes survive --float32

    source.sourceType = "float64";
    EXPECT_EQ(niftiStorageLike(source, false).type, SampleType::Float32);
    EXPECT_NE(niftiStorageLike(source, false).float32Reason.find("float64"), std::string::npos);
    source.sourceType = "uint8";
    source.storedSlope = 0.0;
    EXPECT_EQ(niftiStorageLike(source, false).type, SampleType::Float32);
    EXPECT_FALSE(niftiStorageLike(source, false).float32Reason.empty());

    source.niftiCodes = NiftiCodes{7, 1, 2};  // not a NIfTI code: scanner and mm instead
    EXPECT_EQ(niftiStorageLike(source, false).codes.sform, 1);
    EXPECT_EQ(niftiStorageLike(VolumeMetadata{}, false).codes.qform, 1);  // not from NIfTI
}

TEST(NiftiWriter, AMissingFolderLeavesNothing) {
    test::TempDir dir;
    EXPECT_THROW(writeNifti(dir.path("missing/out.nii.gz"), FloatVolume(openvdb::Coord(2), 1)), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.path("missing")));
}

TEST(NiftiWriter, Int16KeepsItsExtremesRoundsHalfToEvenAndCountsWhatItClamps) {
    test::TempDir dir;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    FloatVolume volume(openvdb::Coord(8, 1, 1), 1);
    volume.values = {-32768.0f, 32767.0f, -40000.0f, 40000.0f, nan, -0.4f, 2.5f, -1.5f};
    NiftiStorage storage;
    storage.type = SampleType::Int16;
    const std::string path = dir.path("ct.nii");
    // -40000, 40000 and NaN do not fit; NaN is stored as 0.
    EXPECT_EQ(writeNifti(path, volume, storage), 3u);
    const DenseVolume back = readNifti(path, ReadOptions{});
    ASSERT_EQ(back.type, SampleType::Int16);
    ASSERT_EQ(back.voxelCount(), 8u);
    const std::int16_t expected[8] = {-32768, 32767, -32768, 32767, 0, 0, 2, -2};
    for (int n = 0; n < 8; ++n) EXPECT_EQ(back.data<std::int16_t>()[n], expected[n]) << n;
}

TEST(NiftiWriter, TwoChannelsAreRefusedByNameAndLeaveNoFile) {
    test::TempDir dir;
    const std::string path = dir.path("two.nii.gz");
    const std::string message =
        test::errorMessageOf<InputError>([&] { writeNifti(path, FloatVolume(openvdb::Coord(2, 2, 2), 2)); });
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("1 or 3 channels"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_TRUE(std::filesystem::is_empty(dir.root()));
}

}  // namespace
}  // namespace gvr
