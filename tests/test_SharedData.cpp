// Every set in ../shared/data ingests with the dimensions, spacing and value
// ranges its README states.

#include "io/Ingest.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

namespace gvr {
namespace {

struct Expected {
    std::string input;
    openvdb::Vec3i dims;
    openvdb::Vec3d spacingMm;
    double valueMin, valueMax;
    int channels;
    std::string sourceType;
};

/// ctest lists the case by its input rather than as raw bytes.
void PrintTo(const Expected& expected, std::ostream* out) { *out << expected.input; }

class SharedDataIngest : public ::testing::TestWithParam<Expected> {};

std::string testName(const ::testing::TestParamInfo<Expected>& info) {
    std::string name = info.param.input.substr(0, info.param.input.find('/'));
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return name + "_" + std::to_string(info.index);
}

TEST_P(SharedDataIngest, MatchesTheReadme) {
    GVR_REQUIRE_SHARED_DATA();
    const Expected& expected = GetParam();
    const IngestResult result = ingest(test::sharedData(expected.input), {});
    const auto metadata = readVolumeMetadata(*result.grid);
    ASSERT_TRUE(metadata);
    EXPECT_EQ(metadata->dims, expected.dims);
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(metadata->spacingMm[axis], expected.spacingMm[axis], 1e-3) << "axis " << axis;
    }
    EXPECT_NEAR(metadata->valueMin, expected.valueMin, 0.5);
    EXPECT_NEAR(metadata->valueMax, expected.valueMax, 0.5);
    EXPECT_EQ(metadata->channels, expected.channels);
    EXPECT_EQ(metadata->sourceType, expected.sourceType);
    EXPECT_EQ(result.grid->getName(), expected.channels == 3 ? "color" : "density");
    EXPECT_EQ(expected.channels == 3, result.grid->isType<openvdb::Vec3SGrid>());
    EXPECT_GT(result.grid->activeVoxelCount(), 0u);
}

// Ranges are the README's where it states them; the others were read once with
// the data's own tools' conventions (uint8 photos span 0..255).
INSTANTIATE_TEST_SUITE_P(
    Readme, SharedDataIngest,
    ::testing::Values(
        Expected{"ct-chest-ricord-512", {512, 512, 255}, {0.703125, 0.703125, 1.25}, -3024, 1857, 1, "int16"},
        Expected{"ct-gantry-tilt-shear/shear.nii.gz", {306, 422, 54}, {0.482, 0.482, 2.371}, -1024, 789, 1, "uint8"},
        Expected{"ct-head-visible-human-png", {512, 512, 234}, {1, 1, 1}, 0, 255, 1, "uint8"},
        Expected{"mri-4d-asl-float32/mpld_asl.nii.gz", {64, 64, 24}, {3.4375, 3.4375, 4.95}, 0, 2839, 1, "float32"},
        Expected{"mri-colin27-aal/ch2.nii.gz", {181, 217, 181}, {1, 1, 1}, 0, 254, 1, "uint8"},
        Expected{"mri-colin27-aal/aal.nii.gz", {181, 217, 181}, {1, 1, 1}, 0, 116, 1, "uint8"},
        Expected{"mri-freesurfer-norm-aparc/norm.mgz", {256, 256, 256}, {1, 1, 1}, 0, 125, 1, "uint8"},
        Expected{"mri-freesurfer-norm-aparc/aparc.a2009s+aseg.mgz", {256, 256, 256}, {1, 1, 1}, 0, 12175, 1, "int32"},
        Expected{"rgb-brainmaps54-cryosection", {512, 304, 57}, {1, 1, 1}, 1.43, 255, 3, "uint8"},
        Expected{"rgb-frog-cryosection/color_png", {640, 482, 137}, {1, 1, 1}, 0, 255, 3, "uint8"},
        Expected{"rgb24-ct-perfusion/ct_perfusion.nii.gz", {256, 286, 15}, {0.781, 0.781, 10.0}, 0, 255, 3, "uint8"}),
    testName);

TEST(SharedData, GantryTiltGivesAShearedTransform) {
    GVR_REQUIRE_SHARED_DATA();
    const IngestResult result = ingest(test::sharedData("ct-gantry-tilt-shear/shear.nii.gz"), {});
    const openvdb::Mat4d m = result.grid->transform().baseMap()->getAffineMap()->getMat4();
    // Row n of OpenVDB's matrix is the world step of index axis n. The sform's
    // off-diagonal 0.153 makes each step along j rise 0.153 mm in z.
    EXPECT_NEAR(m(1, 1), 0.4575, 1e-4);
    EXPECT_NEAR(m(1, 2), 0.1531, 1e-4);
    EXPECT_NEAR(m(2, 2), 2.3708, 1e-4);
    EXPECT_NEAR(m(2, 1), 0.0, 1e-9);
}

TEST(SharedData, DicomSlicesAreSortedByPositionIntoRasWorld) {
    GVR_REQUIRE_SHARED_DATA();
    const IngestResult result = ingest(test::sharedData("ct-chest-ricord-512"), {});
    // Z runs from -349.25 (first after sorting along the normal) up to -31.75.
    const openvdb::Vec3d first = result.grid->indexToWorld(openvdb::Vec3d(0, 0, 0));
    const openvdb::Vec3d last = result.grid->indexToWorld(openvdb::Vec3d(0, 0, 254));
    EXPECT_NEAR(first.z(), -349.25, 1e-3);
    EXPECT_NEAR(last.z(), -31.75, 1e-3);
}

}  // namespace
}  // namespace gvr
