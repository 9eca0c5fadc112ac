// gvr export, eval and probe as a user meets them.

#include "io/formats/ImageFile.h"
#include "io/formats/Readers.h"
#include "tests/TestHelpers.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace gvr {
namespace {

using test::runGvr;

/// A small fitted asset in @a dir, with the fit's own JSON report.
std::string smallAsset(const test::TempDir& dir, nlohmann::json* fitReport = nullptr) {
    const std::string grid = test::smallGrid(dir), asset = dir.path("small.asset");
    const test::CommandResult fit =
        runGvr("fit -q '" + grid + "' -o '" + asset + "' --gaussians 150 --iterations 80 --json", dir);
    EXPECT_EQ(fit.exitCode, 0) << fit.err;
    if (fitReport) *fitReport = nlohmann::json::parse(fit.out);
    return asset;
}

TEST(CliExport, ExportThenEvalAgreesWithTheFit) {
    test::TempDir dir;
    nlohmann::json fit;
    const std::string asset = smallAsset(dir, &fit);
    const std::string output = dir.path("rec.vdb");
    const test::CommandResult exported = runGvr("export -q '" + asset + "' -o '" + output + "' --json", dir);
    ASSERT_EQ(exported.exitCode, 0) << exported.err;
    const nlohmann::json report = nlohmann::json::parse(exported.out);
    EXPECT_EQ(report["dims"], nlohmann::json({24, 20, 16}));
    EXPECT_EQ(report["grids"][0]["name"], "density");

    const test::CommandResult eval = runGvr("eval --json '" + dir.path("small.vdb") + "' '" + output + "'", dir);
    ASSERT_EQ(eval.exitCode, 0) << eval.err;
    const nlohmann::json metrics = nlohmann::json::parse(eval.out);
    for (const char* key : {"mse", "psnr", "fg_psnr", "ssim", "ms_ssim", "peak"}) {
        EXPECT_TRUE(metrics.contains(key)) << key;
    }
    // The same field on the same voxels, with the same threshold rule: the same number.
    EXPECT_NEAR(metrics["psnr"].get<double>(), fit["psnr_db"].get<double>(), 0.01);
    EXPECT_NEAR(metrics["fg_psnr"].get<double>(), fit["fg_psnr_db"].get<double>(), 0.01);
    EXPECT_GT(metrics["ssim"].get<double>(), 0.5);
    EXPECT_EQ(metrics["ms_ssim_scales"], 1);  // 16 voxels deep: too small for more

    // An asset compares as its export, without writing one.
    const test::CommandResult direct = runGvr("eval --json '" + dir.path("small.vdb") + "' '" + asset + "'", dir);
    ASSERT_EQ(direct.exitCode, 0) << direct.err;
    EXPECT_EQ(nlohmann::json::parse(direct.out)["psnr"], metrics["psnr"]);
}

TEST(CliExport, NiftiAndResizedGrids) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    const test::CommandResult run = runGvr("export -q '" + asset + "' -o '" + dir.path("fine.vdb") + "' -o '" +
                                               dir.path("fine.nii.gz") + "' --voxel-size 0.5 --json",
                                           dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    EXPECT_EQ(report["dims"], nlohmann::json({48, 40, 32}));
    EXPECT_EQ(report["outputs"][1]["path"], dir.path("fine.nii.gz"));
    EXPECT_EQ(report["outputs"][1]["format"], "nifti");
    EXPECT_TRUE(std::filesystem::exists(dir.path("fine.nii.gz")));
    const test::CommandResult info = runGvr("info --json '" + dir.path("fine.nii.gz") + "'", dir);
    ASSERT_EQ(info.exitCode, 0) << info.err;
    EXPECT_NE(info.out.find("48"), std::string::npos);

    const test::CommandResult coarse =
        runGvr("export -q '" + asset + "' -o '" + dir.path("coarse.vdb") + "' --resolution 12 --json", dir);
    ASSERT_EQ(coarse.exitCode, 0) << coarse.err;
    EXPECT_EQ(nlohmann::json::parse(coarse.out)["dims"], nlohmann::json({12, 10, 8}));
}

/// A CT ingested with a threshold far above its background: export cuts values
/// in between, and the fit must report the volume with that cut made.
TEST(CliExport, FitEvalOfTheAssetAndEvalOfItsExportReportOnePsnr) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("ct-gantry-tilt-shear/shear.nii.gz");
    const std::string grid = dir.path("ct.vdb"), asset = dir.path("ct.gvr"), exported = dir.path("rec.vdb");
    ASSERT_EQ(runGvr("ingest -q '" + source + "' -o '" + grid + "' --threshold -500", dir).exitCode, 0);
    const test::CommandResult fit = runGvr(
        "fit -q '" + grid + "' -o '" + asset + "' --gaussians 2000 --iterations 40 --solve-iterations 2 --json", dir);
    ASSERT_EQ(fit.exitCode, 0) << fit.err;
    ASSERT_EQ(runGvr("export -q '" + asset + "' -o '" + exported + "'", dir).exitCode, 0);
    const nlohmann::json fitted = nlohmann::json::parse(fit.out);
    for (const std::string& compared : {asset, exported}) {
        const test::CommandResult eval = runGvr("eval --json '" + grid + "' '" + compared + "'", dir);
        ASSERT_EQ(eval.exitCode, 0) << eval.err;
        const nlohmann::json metrics = nlohmann::json::parse(eval.out);
        EXPECT_NEAR(metrics["psnr"].get<double>(), fitted["psnr_db"].get<double>(), 0.01) << compared;
        EXPECT_NEAR(metrics["fg_psnr"].get<double>(), fitted["fg_psnr_db"].get<double>(), 0.01) << compared;
    }
}

TEST(CliExport, TheExtensionChoosesTheFormat) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    const test::CommandResult nifti = runGvr("export -q '" + asset + "' -o '" + dir.path("rec.nii.gz") + "'", dir);
    ASSERT_EQ(nifti.exitCode, 0) << nifti.err;
    EXPECT_EQ(readNifti(dir.path("rec.nii.gz"), {}).dims, (std::array<std::int64_t, 3>{24, 20, 16}));
    EXPECT_FALSE(std::filesystem::exists(dir.path("rec.nii.gz.nii.gz")));

    std::filesystem::create_directory(dir.path("out"));
    for (const std::string& outputs : {"-o '" + dir.path("out/rec.tif") + "'",
                                       "-o '" + dir.path("out/a.vdb") + "' -o '" + dir.path("out/b.vdb") + "'"}) {
        const test::CommandResult refused = runGvr("export -q '" + asset + "' " + outputs, dir);
        EXPECT_EQ(refused.exitCode, 2) << outputs;
        EXPECT_EQ(test::lineCount(refused.err), 1u) << refused.err;
        EXPECT_TRUE(std::filesystem::is_empty(dir.path("out"))) << outputs;
    }
    // The old spelling names the new one.
    const test::CommandResult old =
        runGvr("export -q '" + asset + "' -o '" + dir.path("out/rec.vdb") + "' --format nifti", dir);
    EXPECT_EQ(old.exitCode, 2);
    EXPECT_NE(old.err.find("-o OUT.vdb -o OUT.nii.gz"), std::string::npos) << old.err;
    EXPECT_TRUE(std::filesystem::is_empty(dir.path("out")));
}

TEST(CliIngest, ANiftiOutputIsTheSourceBackInItsOwnDatatype) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("ct-gantry-tilt-shear/shear.nii.gz");
    const test::CommandResult run = runGvr("ingest -q '" + source + "' -o '" + dir.path("ct.nii.gz") + "' --json", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(nlohmann::json::parse(run.out)["outputs"][0]["datatype"], "uint8");
    const DenseVolume original = readNifti(source, {}), back = readNifti(dir.path("ct.nii.gz"), {});
    EXPECT_EQ(back.type, SampleType::UInt8);
    EXPECT_EQ(back.slope, original.slope);
    EXPECT_EQ(back.intercept, original.intercept);
    EXPECT_EQ(back.samples, original.samples);  // nothing below the default threshold was lost
}

/// The gantry-tilt CT is uint8 with scl_slope 7.1, sform and qform code 2 and
/// seconds as its time unit: its export gives all of that back.
TEST(CliExport, ANiftiExportKeepsTheSourcesCodesAndDatatype) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string source = test::sharedData("ct-gantry-tilt-shear/shear.nii.gz");
    const std::string grid = dir.path("ct.vdb"), asset = dir.path("ct.gvr");
    ASSERT_EQ(runGvr("ingest -q '" + source + "' -o '" + grid + "'", dir).exitCode, 0);
    // No amplitude solve: the file is what is tested, and a solve is ten passes over 7M voxels.
    const std::string fit =
        "fit -q '" + grid + "' -o '" + asset + "' --gaussians 400 --iterations 3 --solve-iterations 0";
    ASSERT_EQ(runGvr(fit, dir).exitCode, 0);
    const test::CommandResult exported = runGvr("export -q '" + asset + "' -o '" + dir.path("rec.nii") + "'", dir);
    ASSERT_EQ(exported.exitCode, 0) << exported.err;
    const DenseVolume original = readNifti(source, {}), back = readNifti(dir.path("rec.nii"), {});
    EXPECT_EQ(back.type, original.type);
    EXPECT_EQ(back.slope, original.slope);
    EXPECT_EQ(back.intercept, original.intercept);
    ASSERT_TRUE(back.niftiCodes && original.niftiCodes);
    EXPECT_EQ(back.niftiCodes->sform, original.niftiCodes->sform);
    EXPECT_EQ(back.niftiCodes->qform, original.niftiCodes->qform);
    EXPECT_EQ(back.niftiCodes->xyztUnits, original.niftiCodes->xyztUnits);
    EXPECT_TRUE(back.worldFromIndex.eq(original.worldFromIndex, 1e-4));

    const test::CommandResult wide =
        runGvr("export -q '" + asset + "' -o '" + dir.path("wide.nii") + "' --float32", dir);
    ASSERT_EQ(wide.exitCode, 0) << wide.err;
    EXPECT_EQ(readNifti(dir.path("wide.nii"), {}).type, SampleType::Float32);
}

TEST(CliExport, BadInputLeavesNoFiles) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    std::filesystem::create_directory(dir.path("out"));
    const std::string out = "' -o '" + dir.path("out/x.vdb") + "'";
    test::writeBytes(dir.path("bad.asset"), std::string("GVRASSET") + std::string(40, '\1'));
    for (const std::string& arguments :
         {"export '" + dir.path("bad.asset") + out, "export '" + asset + out + " --voxel-size 0",
          "export '" + asset + out + " -o '" + dir.path("out/x.nii.gz") + "' --voxel-size 1e-7",
          "export '" + asset + "' -o '" + dir.path("out/x.nii.gz") + "' --dcc",
          "export '" + asset + out + " --tf mri",  // --tf belongs to --dcc
          "export '" + asset + out + " --dcc --tf '" + dir.path("missing.json") + "'",
          "export '" + asset + out + " --density-from '" + dir.path("missing.json") + "'",
          "export '" + asset + out + " --like '" + dir.path("bad.asset") + "'"}) {
        const test::CommandResult run = runGvr(arguments, dir);
        EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.err;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_TRUE(std::filesystem::is_empty(dir.path("out"))) << arguments;
    }
}

TEST(CliExport, AHugeLatticeIsRefusedNamingTheFlagOrTheMemory) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    const std::string out = "' -o '" + dir.path("x.vdb") + "'";
    const test::CommandResult tooFine = runGvr("export '" + asset + out + " --resolution 100000", dir);
    EXPECT_EQ(tooFine.exitCode, 2);
    EXPECT_NE(tooFine.err.find("--resolution: 100000 voxels along the longest axis would need more than 2^36"),
              std::string::npos)
        << tooFine.err;
    // 2400 x 2000 x 1600 voxels: below the 2^36 limit, far above this machine's memory.
    const test::CommandResult tooBig = runGvr("export '" + asset + out + " --voxel-size 0.01", dir);
    EXPECT_EQ(tooBig.exitCode, 2);
    EXPECT_NE(tooBig.err.find(asset + ": a volume of 2400x2000x1600 voxels needs"), std::string::npos) << tooBig.err;
    EXPECT_NE(tooBig.err.find("to export, but only"), std::string::npos) << tooBig.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.vdb")));
}

TEST(CliEval, IdenticalInputsPrintInfinity) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const test::CommandResult text = runGvr("eval '" + grid + "' '" + grid + "'", dir);
    ASSERT_EQ(text.exitCode, 0) << text.err;
    EXPECT_NE(text.out.find("PSNR     inf dB"), std::string::npos) << text.out;
    const nlohmann::json metrics = nlohmann::json::parse(runGvr("eval --json '" + grid + "' '" + grid + "'", dir).out);
    EXPECT_TRUE(metrics["psnr"].is_null());
    EXPECT_EQ(metrics["mse"], 0.0);
    EXPECT_DOUBLE_EQ(metrics["ssim"].get<double>(), 1.0);
    EXPECT_DOUBLE_EQ(metrics["ms_ssim"].get<double>(), 1.0);
    EXPECT_EQ(metrics["peak"], 200.0);  // the raw volume's range, 0..200
}

TEST(CliEval, ImagesWithNanAreRefused) {
    test::TempDir dir;
    std::vector<float> pixels(4 * 4 * 4, 0.5f);
    writeImage(dir.path("good.exr"), 4, 4, pixels.data());
    pixels[5] = NAN;
    writeImage(dir.path("nan.exr"), 4, 4, pixels.data());
    const test::CommandResult run = runGvr("eval '" + dir.path("good.exr") + "' '" + dir.path("nan.exr") + "'", dir);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
    EXPECT_NE(run.err.find("1 samples are NaN or Inf"), std::string::npos) << run.err;
}

TEST(CliEval, MismatchedGridsNeedResample) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    ASSERT_EQ(runGvr("export -q '" + asset + "' -o '" + dir.path("fine.vdb") + "' --voxel-size 0.5", dir).exitCode, 0);
    const std::string pair = " '" + dir.path("small.vdb") + "' '" + dir.path("fine.vdb") + "'";
    const test::CommandResult refused = runGvr("eval" + pair, dir);
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_EQ(test::lineCount(refused.err), 1u) << refused.err;
    EXPECT_NE(refused.err.find("--resample"), std::string::npos) << refused.err;
    const test::CommandResult resampled = runGvr("eval --json --resample" + pair, dir);
    ASSERT_EQ(resampled.exitCode, 0) << resampled.err;
    EXPECT_GT(nlohmann::json::parse(resampled.out)["psnr"].get<double>(), 20.0);
}

TEST(CliProbe, ValuesMatchTheExportedGrid) {
    test::TempDir dir;
    const std::string asset = smallAsset(dir);
    ASSERT_EQ(runGvr("export -q '" + asset + "' -o '" + dir.path("rec.vdb") + "'", dir).exitCode, 0);
    const test::CommandResult probe = runGvr("probe --json '" + asset + "' --index 8,10,8 --index 0,0,0", dir);
    ASSERT_EQ(probe.exitCode, 0) << probe.err;
    const nlohmann::json points = nlohmann::json::parse(probe.out)["points"];
    ASSERT_EQ(points.size(), 2u);
    EXPECT_GT(points[0]["value"][0].get<double>(), 100.0);  // the blob's centre holds 200
    EXPECT_GT(points[0]["gaussians"].get<int>(), 0);
    EXPECT_EQ(runGvr("probe '" + asset + "' --index 1,2", dir).exitCode, 2);
    EXPECT_EQ(runGvr("probe '" + asset + "'", dir).exitCode, 2);  // no point at all

    // The same point in world millimetres gives the same value.
    const nlohmann::json world = points[0]["world_mm"];
    const std::string at = std::to_string(world[0].get<double>()) + "," + std::to_string(world[1].get<double>()) + "," +
                           std::to_string(world[2].get<double>());
    const test::CommandResult byWorld = runGvr("probe --json '" + asset + "' --world " + at, dir);
    ASSERT_EQ(byWorld.exitCode, 0) << byWorld.err;
    const nlohmann::json same = nlohmann::json::parse(byWorld.out)["points"][0];
    EXPECT_NEAR(same["value"][0].get<double>(), points[0]["value"][0].get<double>(), 1e-3);
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(same["index"][axis].get<double>(), points[0]["index"][axis].get<double>(), 1e-5);
}

}  // namespace
}  // namespace gvr
