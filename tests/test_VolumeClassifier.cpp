// Presets fitted to a render volume: the default for the data, names in any case,
// the word on a preset that does not suit the data, and the colour scale.

#include "pipeline/Error.h"
#include "render/VolumeClassifier.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <string>

namespace gvr {
namespace {

/// An MRI-like grey volume: 0 to 200, nothing below zero, so not CT in HU.
GridRenderVolume greyVolume() {
    return GridRenderVolume(
        test::makeGrid({20, 20, 20}, [](int i, int j, int k) { return float(i + j + k) * 200.0f / 57.0f; }));
}

bool samePoints(const TransferFunction& a, const TransferFunction& b) {
    if (a.points().size() != b.points().size()) return false;
    for (std::size_t p = 0; p < a.points().size(); ++p) {
        if (a.points()[p].value != b.points()[p].value || a.points()[p].rgba != b.points()[p].rgba) return false;
    }
    return true;
}

TEST(VolumeClassifier, NamesPresetsInAnyCaseAndDefaultsToTheOneForTheData) {
    const GridRenderVolume volume = greyVolume();
    EXPECT_TRUE(samePoints(presetFor(volume, "MRI"), presetFor(volume, "mri")));
    EXPECT_TRUE(samePoints(presetFor(volume, ""), presetFor(volume, defaultPreset(1, volume.statistics()))));
    EXPECT_FALSE(samePoints(presetFor(volume, "ct"), presetFor(volume, "mri")));
}

TEST(VolumeClassifier, SaysWhenAPresetDoesNotSuitTheData) {
    const GridRenderVolume volume = greyVolume();
    std::string mismatch = "unset";
    presetFor(volume, "mri", &mismatch);
    EXPECT_EQ(mismatch, "");
    presetFor(volume, "ct", &mismatch);
    EXPECT_NE(mismatch.find("Hounsfield"), std::string::npos) << mismatch;
}

TEST(VolumeClassifier, RefusesAnUnknownPreset) { EXPECT_THROW(presetFor(greyVolume(), "x-ray-vision"), InputError); }

TEST(VolumeClassifier, ScalesColoursByTheVolumesLargestValue) {
    openvdb::Vec3SGrid::Ptr colour = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    colour->getAccessor().setValue(openvdb::Coord(1, 1, 1), openvdb::Vec3s(50.0f, 200.0f, 100.0f));
    const GridRenderVolume volume(colour);
    const Classifier classifier = volumeClassifier(volume, presetFor(volume, "rgb"));
    EXPECT_EQ(classifier.channels(), 3);
    EXPECT_DOUBLE_EQ(classifier.colourScale(), 1.0 / 200.0);
}

}  // namespace
}  // namespace gvr
