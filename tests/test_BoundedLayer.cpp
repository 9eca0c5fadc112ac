// gvr fit --max-error, as a user runs it: every voxel of the export within the
// bound of the source, read back from the file; the Gaussians alone on request; bad
// bounds refused in one line with no output.

#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "pipeline/QualityMetrics.h"
#include "pipeline/ResidualLayer.h"
#include "tests/TestHelpers.h"
#include "workflow/BoundedLayer.h"
#include "workflow/ComparisonInput.h"

#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

namespace gvr {
namespace {

double exportError(const std::string& source, const std::string& exported) {
    const ComparisonInput a = loadComparisonInput(source, {});
    const ComparisonInput b = loadComparisonInput(exported, {});
    return maxAbsoluteError(a.volume, b.volume);
}

TEST(BoundedLayer, AFitWithMaxErrorExportsEveryVoxelWithinIt) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string asset = dir.path("bounded.gvr");
    const test::CommandResult fit = test::runGvr(
        "fit -q '" + grid + "' --gaussians 60 --iterations 10 --seed 3 --max-error 0.01 --json -o '" + asset + "'",
        dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    const nlohmann::json report = nlohmann::json::parse(fit.out);
    EXPECT_LE(report["residual_layer"]["measured_max_error"].get<double>(), 0.01);
    const test::CommandResult info = test::runGvr("info --json '" + asset + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    EXPECT_NE(info.out.find("\"format_version\": 3"), std::string::npos) << info.out;

    const std::string all = dir.path("all.nii.gz"), preview = dir.path("gaussians.nii.gz");
    ASSERT_EQ(test::runGvr("export -q '" + asset + "' --float32 -o '" + all + "'", dir).exitCode, 0);
    ASSERT_EQ(test::runGvr("export -q '" + asset + "' --float32 --layers gaussians -o '" + preview + "'", dir).exitCode,
              0);
    EXPECT_LE(exportError(grid, all), 0.01);
    EXPECT_GT(exportError(grid, preview), 0.01);  // ten iterations of 60 Gaussians are no copy
    // gvr eval reads the asset with its layer and reports the bound's figure.
    const test::CommandResult eval = test::runGvr("eval --json '" + grid + "' '" + asset + "'", dir);
    ASSERT_EQ(eval.exitCode, 0) << eval.err;
    EXPECT_LE(nlohmann::json::parse(eval.out)["max_error"].get<double>(), 0.01);
    const test::CommandResult evalPreview = test::runGvr("eval --json '" + grid + "' '" + preview + "'", dir);
    ASSERT_EQ(evalPreview.exitCode, 0) << evalPreview.err;
    EXPECT_GT(nlohmann::json::parse(evalPreview.out)["max_error"].get<double>(), 0.01);

    // The bound is on the source's own grid: another is the Gaussians' alone, if asked for.
    const test::CommandResult coarse =
        test::runGvr("export -q '" + asset + "' --resolution 8 -o '" + dir.path("c.vdb") + "'", dir);
    EXPECT_EQ(coarse.exitCode, 2);
    EXPECT_NE(coarse.err.find("--layers gaussians"), std::string::npos) << coarse.err;
    EXPECT_EQ(
        test::runGvr("export -q '" + asset + "' --resolution 8 --layers gaussians -o '" + dir.path("c.vdb") + "'", dir)
            .exitCode,
        0);
}

TEST(BoundedLayer, IntegerDataAtABoundBelowOneIsLossless) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("mri-colin27-aal/ch2.nii.gz");
    const std::string asset = dir.path("ch2.gvr"), out = dir.path("ch2.nii.gz");
    const test::CommandResult fit =
        test::runGvr("fit -q '" + source + "' --gaussians 2000 --iterations 5 --max-error 0.5 -o '" + asset + "'", dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    ASSERT_EQ(test::runGvr("export -q '" + asset + "' -o '" + out + "'", dir).exitCode, 0);  // uint8, as the source
    EXPECT_EQ(exportError(source, out), 0.0);
}

TEST(BoundedLayer, AnAutoBoundIsTheSmallestWithWhichTheAssetFitsTheRatio) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("mri-colin27-aal/ch2.nii.gz");
    const std::string asset = dir.path("auto.gvr"), tighter = dir.path("tighter.gvr");
    const test::CommandResult fit = test::runGvr(
        "fit -q '" + source + "' --ratio 10 --max-error auto --iterations 5 --json -o '" + asset + "'", dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    const nlohmann::json report = nlohmann::json::parse(fit.out);
    EXPECT_GE(report["ratio_vs_raw"].get<double>(), 10.0);
    EXPECT_EQ(report["residual_layer"]["searched_for_ratio"].get<double>(), 10.0);
    const double bound = report["residual_layer"]["max_error"].get<double>();
    EXPECT_LE(report["residual_layer"]["measured_max_error"].get<double>(), bound);
    ASSERT_GE(bound, 1.0);  // ch2 is uint8: bounds are whole samples

    // One sample tighter, over the same Gaussians (400:1 is also the default preview), misses 10:1.
    const test::CommandResult over = test::runGvr("fit -q '" + source + "' --max-error " + std::to_string(bound - 1.0) +
                                                      " --iterations 5 --json -o '" + tighter + "'",
                                                  dir);
    ASSERT_EQ(over.exitCode, 0) << over.err;
    EXPECT_LT(nlohmann::json::parse(over.out)["ratio_vs_raw"].get<double>(), 10.0);

    const test::CommandResult alone =
        test::runGvr("fit -q '" + source + "' --max-error auto -o '" + tighter + "'", dir);
    EXPECT_EQ(alone.exitCode, 2);
    EXPECT_NE(alone.err.find("--ratio"), std::string::npos) << alone.err;
}

TEST(BoundedLayer, AnAutoBoundOnAnOddSlopeLeavesNoVoxelToRounding) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("ct-gantry-tilt-shear/shear.nii.gz");  // uint8, 7.1098 HU a sample
    const test::CommandResult fit = test::runGvr("fit -q '" + source +
                                                     "' --ratio 10 --max-error auto --iterations 20 "
                                                     "--json -o '" +
                                                     dir.path("g.gvr") + "'",
                                                 dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    const nlohmann::json layer = nlohmann::json::parse(fit.out)["residual_layer"];
    EXPECT_EQ(layer["exact_voxels"].get<std::size_t>(), 0u) << layer;
    EXPECT_LE(layer["measured_max_error"].get<double>(), layer["max_error"].get<double>());
}

TEST(BoundedLayer, ASmallVolumesPreviewKeepsAFewGaussiansPastItsRatio) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir), asset = dir.path("small.gvr");  // 7.5 KiB: 400:1 is 19 bytes
    const test::CommandResult fit =
        test::runGvr("fit -q '" + grid + "' --max-error 2 --iterations 3 --json -o '" + asset + "'", dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    const nlohmann::json report = nlohmann::json::parse(fit.out);
    EXPECT_EQ(report["gaussians"].get<std::size_t>(), kBoundedPreviewGaussians);
    EXPECT_LE(report["residual_layer"]["measured_max_error"].get<double>(), 2.0);
    // A ratio the whole asset cannot reach is refused in one line, naming it.
    const test::CommandResult tight = test::runGvr(
        "fit -q '" + grid + "' --ratio 50 --max-error auto --iterations 3 -o '" + dir.path("t.gvr") + "'", dir);
    EXPECT_EQ(tight.exitCode, 2);
    EXPECT_EQ(test::lineCount(tight.err), 1u) << tight.err;
    EXPECT_NE(tight.err.find("no error bound fits 50:1"), std::string::npos) << tight.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("t.gvr")));
}

TEST(BoundedLayer, ABadBoundIsRefusedInOneLineBeforeTheFit) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    for (const std::string bad : {"nan", "-1", "abc", "1e999", "5%%x"}) {
        const std::string out = dir.path("out.gvr");
        const test::CommandResult run = test::runGvr(
            "fit -q '" + grid + "' --gaussians 20 --iterations 2 --max-error '" + bad + "' -o '" + out + "'", dir);
        EXPECT_EQ(run.exitCode, 2) << bad;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_NE(run.err.find("max-error"), std::string::npos) << run.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << bad;
    }
}

/// @a bytes with its header's residual edited by @a edit, and the CRC made right again.
std::string withEditedResidual(const std::string& bytes, const std::function<void(nlohmann::json&)>& edit) {
    std::uint32_t headerBytes;
    std::memcpy(&headerBytes, bytes.data() + 12, 4);
    nlohmann::json header = nlohmann::json::parse(bytes.substr(16, headerBytes));
    edit(header["residual"]);
    const std::string text = header.dump();
    std::string out = bytes.substr(0, 12) + test::littleEndian32(std::uint32_t(text.size())) + text +
                      bytes.substr(16 + headerBytes, bytes.size() - 16 - headerBytes - 4);
    return out +
           test::littleEndian32(std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(out.data()), uInt(out.size()))));
}

TEST(BoundedLayer, ProbeAndRenderReadTheLayerAndTheGaussiansOnRequest) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir), asset = dir.path("b.gvr");
    ASSERT_EQ(
        test::runGvr("fit -q '" + grid + "' --gaussians 20 --iterations 3 --max-error 0.5 -o '" + asset + "'", dir)
            .exitCode,
        0);  // lossless: the source is uint8
    const auto probed = [&](const std::string& layers) {
        const test::CommandResult run =
            test::runGvr("probe --json '" + asset + "' --index 8,10,8 --layers " + layers, dir);
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return nlohmann::json::parse(run.out)["points"][0]["value"][0].get<double>();
    };
    EXPECT_NEAR(probed("all"), 200.0, 0.5);                 // the blob's centre, as stored
    EXPECT_GT(std::abs(probed("gaussians") - 200.0), 0.5);  // 20 Gaussians in three iterations

    // Lossless, the asset draws as its source does, pixel for pixel; its Gaussians do not.
    const auto rendered = [&](const std::string& input, const std::string& extra, const std::string& name) {
        const std::string frame = dir.path(name);
        const test::CommandResult run =
            test::runGvr("render -q '" + input + "' --size 48x48 --tf mri " + extra + " -o '" + frame + "'", dir);
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return test::readBytes(frame);
    };
    const std::string source = rendered(grid, "", "source.png");
    EXPECT_EQ(rendered(asset, "", "all.png"), source);
    EXPECT_NE(rendered(asset, "--layers gaussians", "preview.png"), source);
}

TEST(BoundedLayer, ALayerThatLiesAboutItsSizesIsRefusedNamingTheFile) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir), asset = dir.path("b.gvr");
    ASSERT_EQ(
        test::runGvr("fit -q '" + grid + "' --gaussians 30 --iterations 3 --max-error 0.05 -o '" + asset + "'", dir)
            .exitCode,
        0);
    const std::string bytes = test::readBytes(asset);
    ASSERT_NO_THROW(decodeAsset(bytes, asset));
    const std::vector<std::function<void(nlohmann::json&)>> lies = {
        [](nlohmann::json& r) { r["section_bytes"] = r["section_bytes"].get<std::uint64_t>() + (1u << 30); },
        [](nlohmann::json& r) { r["exact_voxels"] = std::uint64_t(1) << 40; },
        [](nlohmann::json& r) { r["coder"] = "huffman"; },
        [](nlohmann::json& r) { r["bound"] = -1.0; },
        [](nlohmann::json& r) { r["domain"] = "complex"; },
        [](nlohmann::json& r) { r["reconstruction_crc32"] = r["reconstruction_crc32"].get<std::uint32_t>() ^ 1u; },
    };
    for (std::size_t n = 0; n < lies.size(); ++n) {
        const std::string lying = dir.path("lie" + std::to_string(n) + ".gvr");
        test::writeBytes(lying, withEditedResidual(bytes, lies[n]));
        const test::CommandResult run = test::runGvr("export -q '" + lying + "' -o '" + dir.path("x.vdb") + "'", dir);
        EXPECT_EQ(run.exitCode, 2) << n << ": " << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_NE(run.err.find(lying), std::string::npos) << run.err;
        EXPECT_FALSE(std::filesystem::exists(dir.path("x.vdb")));
    }
}

TEST(BoundedLayer, AnAssetSavedAgainKeepsItsLayerByteForByte) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir), asset = dir.path("b.gvr");
    ASSERT_EQ(
        test::runGvr("fit -q '" + grid + "' --gaussians 40 --iterations 4 --max-error 0.05 -o '" + asset + "'", dir)
            .exitCode,
        0);
    GaussianAsset read = readAsset(asset);
    ASSERT_TRUE(read.residual);
    EXPECT_EQ(encodeAsset(read), test::readBytes(asset));  // as Python's asset.save() writes it
}

TEST(BoundedLayer, ARelativeBoundIsAShareOfTheDataRange) {
    EXPECT_DOUBLE_EQ(parseMaxError("0.5%", 254.0), 1.27);
    EXPECT_DOUBLE_EQ(parseMaxError("3", 254.0), 3.0);
    EXPECT_THROW(parseMaxError("%", 254.0), InputError);
    EXPECT_THROW(parseMaxError("2 HU", 254.0), InputError);
}

}  // namespace
}  // namespace gvr
