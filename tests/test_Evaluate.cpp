// gvr eval's comparison in memory: PSNR from the reference's data range or a given
// peak, the foreground rules, and the inputs it must refuse, each naming the culprit.

#include "pipeline/Error.h"
#include "workflow/Evaluate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace gvr {
namespace {

constexpr int kSide = 16;

/// Values 0 to 100 repeating, plus @a add; the data range is 100.
ComparisonInput ramp(float add, int channels = 1, int side = kSide) {
    ComparisonInput input;
    input.volume = FloatVolume(openvdb::Coord(side), channels);
    for (std::size_t n = 0; n < input.volume.values.size(); ++n) {
        input.volume.values[n] = float(n / std::size_t(channels) % 101) + add;
    }
    input.dataRange = 100.0;
    return input;
}

std::size_t voxelsAbove(const ComparisonInput& input, float cut) {
    std::size_t count = 0;
    for (float v : input.volume.values) count += v > cut;
    return count;
}

TEST(Evaluate, AnOffsetOfOneOverARangeOfAHundredIsFortyDecibels) {
    const EvalResult e = evaluate(ramp(0.0f), ramp(1.0f), EvalOptions(), "ref", "test");
    EXPECT_DOUBLE_EQ(e.peak, 100.0);
    EXPECT_NEAR(e.mse, 1.0, 1e-12);
    EXPECT_NEAR(e.psnr, 40.0, 1e-9);
    // Without a threshold or active voxels, the foreground is what lies above the reference's minimum.
    EXPECT_EQ(e.foregroundVoxels, voxelsAbove(ramp(0.0f), 0.0f));
    EXPECT_NEAR(e.foregroundMse, 1.0, 1e-12);
    EXPECT_EQ(e.foregroundRule, "reference above its minimum");
    EXPECT_LT(e.ssim, 1.0);
}

TEST(Evaluate, AGivenPeakAndThresholdReplaceTheDefaults) {
    EvalOptions options;
    options.peak = 10.0;
    options.threshold = 50.0;
    const EvalResult e = evaluate(ramp(0.0f), ramp(1.0f), options, "ref", "test");
    EXPECT_NEAR(e.psnr, 20.0, 1e-9);
    EXPECT_EQ(e.foregroundVoxels, voxelsAbove(ramp(0.0f), 50.0f));
    EXPECT_NE(e.foregroundRule.find("reference above 50"), std::string::npos) << e.foregroundRule;
}

TEST(Evaluate, IdenticalVolumesAreInfiniteDecibelsAndJsonSaysInf) {
    const EvalResult e = evaluate(ramp(0.0f), ramp(0.0f), EvalOptions(), "ref", "test");
    EXPECT_EQ(e.mse, 0.0);
    EXPECT_TRUE(std::isinf(e.psnr));
    EXPECT_DOUBLE_EQ(e.ssim, 1.0);
    const nlohmann::json json = evalResultJson(e);
    EXPECT_TRUE(json["psnr"].is_null());  // JSON has no infinity; the MSE beside it is 0
    EXPECT_EQ(json["mse"], 0.0);
    EXPECT_EQ(json["fg_voxels"], e.foregroundVoxels);
}

/// The message of the InputError that @a call throws, or "" when it throws none.
template <typename Call>
std::string refusal(const Call& call) {
    try {
        call();
    } catch (const InputError& error) {
        return error.what();
    }
    return "";
}

// Voxels a source's format marks as no data count in no measure: a fit's air beside
// the chest's -3024 HU padding once weighed more than its body.
TEST(Evaluate, TheVoxelsLeftOutCountInNoMeasure) {
    ComparisonInput reference = ramp(0.0f);
    ComparisonInput test = ramp(0.0f);
    reference.excluded.assign(reference.volume.voxelCount(), 0);
    for (std::size_t n = 0; n < reference.excluded.size(); n += 3) {
        reference.excluded[n] = 1;
        test.volume.values[n] += 5000.0f;  // wrong only where nothing is known
    }
    reference.excludedVoxels = std::size_t(std::count(reference.excluded.begin(), reference.excluded.end(), 1));
    reference.readAs = "the source as read";
    const EvalResult e = evaluate(reference, test, EvalOptions(), "ref", "test");
    EXPECT_EQ(e.mse, 0.0);
    EXPECT_TRUE(std::isinf(e.psnr));
    EXPECT_NEAR(e.ssim, 1.0, 1e-9);
    EXPECT_EQ(e.excludedVoxels, reference.excludedVoxels);
    EXPECT_EQ(evalResultJson(e)["reference_read_as"], "the source as read");
    EXPECT_EQ(evalResultJson(e)["excluded_voxels"], reference.excludedVoxels);
    // Elsewhere, every voxel counts.
    test.volume.values[1] += 10.0f;
    EXPECT_GT(evaluate(reference, test, EvalOptions(), "ref", "test").mse, 0.0);
}

TEST(Evaluate, RefusesMismatchesAndAConstantReferenceNamingTheCulprit) {
    const std::string channels = refusal([] { evaluate(ramp(0.0f), ramp(0.0f, 3), EvalOptions(), "ref", "test"); });
    EXPECT_EQ(channels.rfind("test: has 3 channel(s), the reference 1", 0), 0u) << channels;

    const std::string dims = refusal([] { evaluate(ramp(0.0f), ramp(0.0f, 1, 8), EvalOptions(), "ref", "test"); });
    EXPECT_EQ(dims.rfind("test: is 8x8x8", 0), 0u) << dims;
    EXPECT_NE(dims.find("resample"), std::string::npos) << dims;

    ComparisonInput flat = ramp(0.0f);
    flat.dataRange = 0.0;
    const std::string constant = refusal([&] { evaluate(flat, ramp(0.0f), EvalOptions(), "ref", "test"); });
    EXPECT_EQ(constant.rfind("ref: has no data range", 0), 0u) << constant;

    EvalOptions nanThreshold;
    nanThreshold.threshold = NAN;
    EXPECT_FALSE(refusal([&] { evaluate(ramp(0.0f), ramp(1.0f), nanThreshold, "ref", "test"); }).empty());
}

TEST(Evaluate, ResamplesOntoTheReferenceWhenAsked) {
    EvalOptions options;
    options.resample = true;
    ComparisonInput coarse;
    coarse.volume = FloatVolume(openvdb::Coord(8), 1);
    std::fill(coarse.volume.values.begin(), coarse.volume.values.end(), 7.0f);
    ComparisonInput reference = ramp(0.0f);
    std::fill(reference.volume.values.begin(), reference.volume.values.end(), 7.0f);
    reference.volume.values[0] = 107.0f;  // a data range to measure against
    const EvalResult e = evaluate(reference, coarse, options, "ref", "test");
    EXPECT_EQ(e.peak, 100.0);
    EXPECT_TRUE(std::isfinite(e.psnr));  // compared voxel for voxel, not refused
}

TEST(Evaluate, ADifferenceImageIsWrittenOnlyForTwoRenderingsAndWithAPositiveGain) {
    const std::string path = testing::TempDir() + "gvr_eval_difference.exr";
    std::remove(path.c_str());
    EvalOptions options;
    options.differenceImage = path;
    const std::string volumes = refusal([&] { evaluate(ramp(0.0f), ramp(1.0f), options, "ref", "test"); });
    EXPECT_EQ(volumes.rfind("`difference`: needs two RGBA images", 0), 0u) << volumes;
    EXPECT_FALSE(std::ifstream(path).good()) << "no output after a refusal";

    ComparisonInput image;
    image.isImage = true;
    image.volume = FloatVolume(openvdb::Coord(5, 3, 1), 4);
    image.dataRange = 1.0;
    ComparisonInput brighter = image;
    brighter.volume.values[4 * 7] = brighter.volume.values[4 * 7 + 3] = 0.5f;  // pixel (2, 1) red, half opaque
    options.differenceGain = 0.0f;
    EXPECT_EQ(refusal([&] { evaluate(image, brighter, options, "ref", "test"); }).rfind("`difference_gain`", 0), 0u);
    EXPECT_FALSE(std::ifstream(path).good());

    options.differenceGain = 2.0f;
    evaluate(image, brighter, options, "ref", "test");
    const ComparisonInput written = loadComparisonInput(path, IngestOptions());
    ASSERT_EQ(written.volume.dims, openvdb::Coord(5, 3, 1));
    // Red: 0.5 over black and 0 over white; green: 0 and 0.5. Each RMS 0.5 / sqrt 2.
    EXPECT_NEAR(written.volume.values[4 * 7], 2.0f * 0.5f / std::sqrt(2.0f), 1e-5);
    EXPECT_NEAR(written.volume.values[4 * 7 + 1], 2.0f * 0.5f / std::sqrt(2.0f), 1e-5);
    EXPECT_EQ(written.volume.values[4 * 6], 0.0f) << "a pixel neither covers";
    std::remove(path.c_str());
}

TEST(Evaluate, RenderingQualityWantsTwoRgbaImagesOfOneShape) {
    FloatVolume rgba(openvdb::Coord(4, 4, 1), 4), grey(openvdb::Coord(4, 4, 1), 1);
    EXPECT_THROW(renderingQuality(rgba, grey), std::invalid_argument);
    const RenderingQuality same = renderingQuality(rgba, rgba);
    EXPECT_TRUE(std::isinf(same.psnr));
}

}  // namespace
}  // namespace gvr
