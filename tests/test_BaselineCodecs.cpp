// The reference codecs of gvr baseline: their error bounds, stream sizes, and
// reconstructions that stand in for the source.

#include "io/GridBuilder.h"
#include "io/formats/GridFile.h"
#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"
#include "workflow/BaselineCodecs.h"
#include "workflow/ZfpStream.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace gvr {
namespace {

/// CT-like: air at -1000 HU around a soft body, and -3024 padding in one corner,
/// the volume's minimum, which ingest makes the inactive voxels.
openvdb::GridBase::Ptr ctLikeGrid(openvdb::Vec3d spacingMm = openvdb::Vec3d(1.0)) {
    return test::makeGrid(
        {24, 20, 16},
        [](int i, int j, int k) {
            if (i + j + k < 6) return -3024.0f;
            const double d2 = (i - 12) * (i - 12) + (j - 9) * (j - 9) + (k - 7) * (k - 7);
            return float(-1000.0 + 1060.0 * std::exp(-d2 / 40.0) + 3.7 * std::sin(0.9 * i + 0.4 * j));
        },
        spacingMm);
}

/// Colour in 0..255 per channel, black (the minimum luminance) in one corner.
openvdb::GridBase::Ptr rgbGrid() {
    const openvdb::Coord dims(12, 10, 8);
    std::vector<float> values;
    for (int k = 0; k < dims.z(); ++k) {
        for (int j = 0; j < dims.y(); ++j) {
            for (int i = 0; i < dims.x(); ++i) {
                const bool black = i + j + k < 3;
                values.push_back(black ? 0.0f : float(20 * i + 3 * k));
                values.push_back(black ? 0.0f : float(25 * j));
                values.push_back(black ? 0.0f : float(255 - 30 * k + i));
            }
        }
    }
    DenseVolume volume = test::makeVolume<float>({dims.x(), dims.y(), dims.z()}, values, SampleType::Float32, 3);
    GridBuildSettings settings;
    settings.sourceFile = "synthetic-rgb";
    return buildGrid(volume, settings);
}

FloatVolume samplesOf(const openvdb::GridBase& grid) { return sampleGrid(grid, volumeBox(grid)); }

float maxAbsError(const FloatVolume& a, const FloatVolume& b) {
    EXPECT_EQ(a.values.size(), b.values.size());
    float worst = 0.0f;
    for (std::size_t n = 0; n < std::min(a.values.size(), b.values.size()); ++n) {
        worst = std::max(worst, std::abs(a.values[n] - b.values[n]));
    }
    return worst;
}

BaselineSettings zfpAccuracy(double tolerance) {
    BaselineSettings settings;
    settings.tolerance = tolerance;
    return settings;
}

BaselineSettings withMethod(BaselineMethod method) {
    BaselineSettings settings;
    settings.method = method;
    return settings;
}

TEST(BaselineZfp, AccuracyModeBoundsTheError) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    // Tolerances between powers of two too: zfp alone would round 5 down to 4.
    for (double tolerance : {0.3, 0.5, 4.0, 5.0, 64.0, 90.0}) {
        const BaselineResult result = runBaseline(*source, zfpAccuracy(tolerance), dir.path("s.zfp"));
        EXPECT_EQ(result.tolerance, tolerance);
        EXPECT_EQ(result.streamBytes, std::filesystem::file_size(dir.path("s.zfp")));
        EXPECT_LT(result.streamBytes, 24u * 20 * 16 * 4 / 2) << "tolerance " << tolerance;
        const float error = maxAbsError(samplesOf(*source), samplesOf(*result.reconstruction));
        EXPECT_LE(error, tolerance);
        EXPECT_GT(error, 0.0f);  // lossy, so the comparison itself is not vacuous
    }
}

TEST(BaselineZfp, FixedRateStreamIsRateTimesValues) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    const std::uint64_t values = 24 * 20 * 16;
    for (double rate : {2.0, 4.0, 8.0}) {
        BaselineSettings settings = withMethod(BaselineMethod::ZfpRate);
        settings.rate = rate;
        const BaselineResult result = runBaseline(*source, settings, dir.path("s.zfp"));
        EXPECT_EQ(result.rate, rate);
        // Every axis is a multiple of zfp's 4-voxel blocks, so the payload is exact; the header is 48 bytes.
        EXPECT_EQ(double(result.streamBytes), 48.0 + rate * double(values) / 8.0);
        EXPECT_NEAR(result.bitsPerValue(), rate + 48.0 * 8.0 / double(values), 1e-9);
    }
}

TEST(BaselineZfp, TargetBytesSearchLandsWithinFivePercent) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    const std::uint64_t reachable = runBaseline(*source, zfpAccuracy(2.0), dir.path("s.zfp")).streamBytes;
    BaselineSettings settings;
    settings.targetBytes = reachable + reachable / 50;  // 2% above a size zfp can make
    const BaselineResult found = runBaseline(*source, settings, dir.path("s.zfp"));
    ASSERT_TRUE(found.matched.has_value());
    EXPECT_TRUE(*found.matched);
    EXPECT_LE(std::abs(double(found.streamBytes) - double(*settings.targetBytes)),
              0.05 * double(*settings.targetBytes));
    ASSERT_TRUE(found.tolerance.has_value());
    EXPECT_LE(maxAbsError(samplesOf(*source), samplesOf(*found.reconstruction)), *found.tolerance);

    // Between the sizes of two powers of two, where zfp's own tolerance steps cannot land.
    const std::uint64_t at2 = reachable, at4 = runBaseline(*source, zfpAccuracy(4.0), dir.path("s.zfp")).streamBytes;
    // More than 1.05^2 apart, so neither step is within 5 % of their geometric mean.
    ASSERT_GT(double(at2) / double(at4), 1.11) << "the steps are too close to test between them";
    settings.targetBytes = std::uint64_t(std::sqrt(double(at2) * double(at4)));
    const BaselineResult between = runBaseline(*source, settings, dir.path("s.zfp"));
    EXPECT_TRUE(between.matched.value_or(false));
    EXPECT_NEAR(double(between.streamBytes) / double(*settings.targetBytes), 1.0, 0.05);
    EXPECT_GT(*between.tolerance, 2.0);
    EXPECT_LT(*between.tolerance, 4.0);

    settings.targetBytes = 10;  // below any stream: the smallest one is kept, not an error
    const BaselineResult closest = runBaseline(*source, settings, dir.path("s.zfp"));
    EXPECT_EQ(closest.matched, false);
    EXPECT_GT(closest.streamBytes, 10u);
    EXPECT_LT(closest.streamBytes, reachable);
    EXPECT_TRUE(std::filesystem::exists(dir.path("s.zfp")));
}

TEST(BaselineZfp, RgbRoundTripsPerChannel) {
    test::TempDir dir;
    const auto source = rgbGrid();
    const BaselineResult result = runBaseline(*source, zfpAccuracy(0.5), dir.path("s.zfp"));
    EXPECT_EQ(result.channels, 3);
    ASSERT_TRUE(result.reconstruction->isType<openvdb::Vec3SGrid>());
    EXPECT_EQ(result.reconstruction->getName(), "color");
    const float error = maxAbsError(samplesOf(*source), samplesOf(*result.reconstruction));
    EXPECT_LE(error, 0.5f);
    EXPECT_GT(error, 0.0f);

    BaselineSettings rate = withMethod(BaselineMethod::ZfpRate);
    rate.rate = 4.0;
    const BaselineResult fixed = runBaseline(*source, rate, dir.path("r.zfp"));
    // zfp codes whole 4^3 blocks: 3 x 3 x 2 of them per channel, after a 64-byte header.
    EXPECT_EQ(fixed.streamBytes, 64u + 3 * (3 * 3 * 2) * 64 * 4 / 8);
}

TEST(BaselineZfp, DamagedStreamsAreInputErrorsNamingTheFile) {
    test::TempDir dir;
    const FloatVolume volume = samplesOf(*ctLikeGrid());
    const std::string stream = encodeZfp(volume, {ZfpMode::FixedAccuracy, 1.0});
    writeZfpFile(dir.path("good.zfp"), stream);
    EXPECT_EQ(readZfpFile(dir.path("good.zfp")).dims, volume.dims);

    std::string hugeDims = stream;
    const std::uint32_t huge = 0x40000000u;
    for (int a = 0; a < 3; ++a) std::memcpy(hugeDims.data() + 16 + 4 * a, &huge, sizeof huge);
    std::string badVersion = stream;
    badVersion[8] = 7;
    std::string hugeCount = stream;
    const std::uint64_t count = std::uint64_t(1) << 40;
    std::memcpy(hugeCount.data() + 40, &count, sizeof count);
    const std::pair<std::string, std::string> damaged[] = {{"truncated.zfp", stream.substr(0, stream.size() / 2)},
                                                           {"header-only.zfp", stream.substr(0, 20)},
                                                           {"trailing.zfp", stream + "xx"},
                                                           {"magic.zfp", "GVRASSET" + stream.substr(8)},
                                                           {"dims.zfp", hugeDims},
                                                           {"version.zfp", badVersion},
                                                           {"count.zfp", hugeCount},
                                                           {"empty.zfp", ""}};
    for (const auto& [name, bytes] : damaged) {
        const std::string path = dir.path(name);
        test::writeBytes(path, bytes);
        try {
            readZfpFile(path);
            ADD_FAILURE() << name << " was accepted";
        } catch (const InputError& error) {
            EXPECT_EQ(std::string(error.what()).rfind(path + ": ", 0), 0u) << error.what();
        }
    }
}

TEST(BaselineVdb, BloscIsExact) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    const BaselineResult result = runBaseline(*source, withMethod(BaselineMethod::VdbBlosc), dir.path("s.vdb"));
    const FloatVolume before = samplesOf(*source), after = samplesOf(*result.reconstruction);
    EXPECT_EQ(before.values, after.values);
    EXPECT_EQ(before.foreground, after.foreground);
    EXPECT_EQ(result.reconstruction->activeVoxelCount(), source->activeVoxelCount());
    EXPECT_FALSE(result.tolerance || result.rate || result.factor || result.matched);
}

TEST(BaselineVdb, HalfIsWithinHalfPrecision) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    const BaselineResult result = runBaseline(*source, withMethod(BaselineMethod::VdbHalf), dir.path("s.vdb"));
    const FloatVolume before = samplesOf(*source), after = samplesOf(*result.reconstruction);
    ASSERT_EQ(before.values.size(), after.values.size());
    std::size_t rounded = 0;
    for (std::size_t n = 0; n < before.values.size(); ++n) {
        const float v = before.values[n];
        EXPECT_LE(std::abs(after.values[n] - v), std::ldexp(std::abs(v), -11)) << "voxel " << n << " was " << v;
        rounded += after.values[n] != v;
    }
    EXPECT_GT(rounded, 0u);  // the floats really went through half

    const auto bright = test::makeGrid({8, 8, 8}, [](int i, int, int) { return 1e5f * float(i); });
    EXPECT_THROW(runBaseline(*bright, withMethod(BaselineMethod::VdbHalf), dir.path("b.vdb")), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.path("b.vdb")));
}

TEST(BaselineDownsample, LinearRampSurvivesInTheInterior) {
    test::TempDir dir;
    const auto ramp = test::makeGrid({16, 12, 8}, [](int i, int j, int k) { return float(i + 2 * j + 3 * k); });
    BaselineSettings settings = withMethod(BaselineMethod::Downsample);
    settings.factor = 2;
    const BaselineResult result = runBaseline(*ramp, settings, dir.path("s.vdb"));
    EXPECT_EQ(result.factor, 2);
    const FloatVolume coarse = samplesOf(*chooseVolumeGrid(*readGridFile(dir.path("s.vdb")), "s.vdb"));
    EXPECT_EQ(coarse.dims, openvdb::Coord(8, 6, 4));
    const FloatVolume after = samplesOf(*result.reconstruction);
    for (int k = 1; k < 7; ++k) {
        for (int j = 1; j < 11; ++j) {
            for (int i = 1; i < 15; ++i)
                EXPECT_NEAR(*after.at(i, j, k), i + 2 * j + 3 * k, 1e-4) << i << "," << j << "," << k;
        }
    }
    EXPECT_GT(std::abs(*after.at(0, 0, 0) - 0.0f), 1.0f);  // the edges clamp, so the test can tell
}

TEST(BaselineDownsample, PartialBoxesAverageTheVoxelsTheyHave) {
    test::TempDir dir;
    const auto source = test::makeGrid({5, 4, 3}, [](int i, int j, int k) { return float(1 + i + 10 * j + 100 * k); });
    BaselineSettings settings = withMethod(BaselineMethod::Downsample);
    settings.factor = 2;
    runBaseline(*source, settings, dir.path("s.vdb"));
    const FloatVolume coarse = samplesOf(*chooseVolumeGrid(*readGridFile(dir.path("s.vdb")), "s.vdb"));
    ASSERT_EQ(coarse.dims, openvdb::Coord(3, 2, 2));
    EXPECT_FLOAT_EQ(*coarse.at(0, 0, 0), 1 + 0.5f + 5 + 50);  // a full 2x2x2 box
    EXPECT_FLOAT_EQ(*coarse.at(2, 0, 0), 1 + 4 + 5 + 50);     // i = 4 alone
    EXPECT_FLOAT_EQ(*coarse.at(2, 1, 1), 1 + 4 + 25 + 200);   // i = 4, j = 2..3, k = 2 alone
}

TEST(BaselineDownsample, AFactorBeyondTheLongestAxisIsRefused) {
    // 2147483647 once overflowed the coarse dimensions, then crashed.
    test::TempDir dir;
    const auto source = test::makeGrid({5, 4, 3}, [](int i, int, int) { return float(1 + i); });
    BaselineSettings settings = withMethod(BaselineMethod::Downsample);
    settings.factor = 5;
    EXPECT_NO_THROW(runBaseline(*source, settings, dir.path("s.vdb")));
    for (int factor : {6, 2147483647}) {
        settings.factor = factor;
        try {
            runBaseline(*source, settings, dir.path("t.vdb"));
            ADD_FAILURE() << "factor " << factor << " was accepted";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find("exceeds the volume's longest axis (5 voxels)"), std::string::npos)
                << error.what();
        }
        EXPECT_FALSE(std::filesystem::exists(dir.path("t.vdb")));
    }
}

TEST(BaselineReconstruction, StandsOnTheSourceLatticeWithItsMetadataAndRule) {
    test::TempDir dir;
    std::vector<float> values;
    for (int k = 0; k < 16; ++k) {
        for (int j = 0; j < 20; ++j) {
            for (int i = 0; i < 24; ++i) values.push_back(float(-1000 + 90 * i + 17 * j - 11 * k));
        }
    }
    DenseVolume volume = test::makeVolume<float>({24, 20, 16}, values, SampleType::Float32);
    const double rows[3][4] = {{0.5, 0.1, 0.0, -40.0}, {0.0, 0.7, 0.0, 12.5}, {0.0, 0.0, 1.2, 3.0}};
    volume.worldFromIndex = worldFromIndexRows(rows);  // sheared and anisotropic
    volume.modality = "CT";
    GridBuildSettings build;
    build.sourceFile = "sheared.nii.gz";
    build.threshold = -500.0;
    const auto source = buildGrid(volume, build);
    const VolumeMetadata expected = *readVolumeMetadata(*source);

    BaselineSettings settings[5];
    settings[0] = zfpAccuracy(1.0);
    settings[1] = withMethod(BaselineMethod::ZfpRate);
    settings[1].rate = 6.0;
    settings[2] = withMethod(BaselineMethod::VdbBlosc);
    settings[3] = withMethod(BaselineMethod::VdbHalf);
    settings[4] = withMethod(BaselineMethod::Downsample);
    settings[4].factor = 3;
    for (const BaselineSettings& s : settings) {
        const std::string name = baselineMethodName(s.method);
        const BaselineResult result = runBaseline(*source, s, dir.path(name + ".stream"));
        const openvdb::GridBase& recon = *result.reconstruction;
        EXPECT_EQ(recon.getName(), "density") << name;
        EXPECT_TRUE(recon.isType<openvdb::FloatGrid>()) << name;
        EXPECT_EQ(recon.getGridClass(), openvdb::GRID_FOG_VOLUME) << name;
        EXPECT_EQ(recon.transform(), source->transform()) << name;
        EXPECT_EQ(volumeBox(recon), volumeBox(*source)) << name;
        const auto metadata = readVolumeMetadata(recon);
        ASSERT_TRUE(metadata) << name;
        EXPECT_EQ(metadata->sourceFile, expected.sourceFile);
        EXPECT_EQ(metadata->modality, "CT");
        EXPECT_EQ(metadata->dims, expected.dims);
        EXPECT_EQ(metadata->spacingMm, expected.spacingMm);
        EXPECT_EQ(metadata->valueMin, expected.valueMin);
        EXPECT_EQ(metadata->valueMax, expected.valueMax);
        EXPECT_EQ(metadata->background, expected.background);
        EXPECT_EQ(metadata->threshold, -500.0);
        EXPECT_EQ(result.voxels, 24u * 20 * 16);
        // The source's rule: active exactly where the value lies above its threshold.
        const FloatVolume after = samplesOf(recon);
        std::size_t active = 0;
        for (std::size_t n = 0; n < after.voxelCount(); ++n) {
            EXPECT_EQ(after.foreground[n] != 0, after.values[n] > -500.0f) << name << " voxel " << n;
            active += after.foreground[n];
        }
        EXPECT_GT(active, 0u) << name;
        EXPECT_LT(active, after.voxelCount()) << name;
    }
}

TEST(BaselineReconstruction, SourceWithoutThresholdGetsNone) {
    test::TempDir dir;
    const auto source = ctLikeGrid();
    ASSERT_FALSE(readVolumeMetadata(*source)->threshold);
    const BaselineResult result = runBaseline(*source, zfpAccuracy(8.0), dir.path("s.zfp"));
    EXPECT_FALSE(readVolumeMetadata(*result.reconstruction)->threshold);
}

TEST(BaselineReconstruction, StreamSizeDoesNotDependOnWhereItIsWritten) {
    test::TempDir dir;
    std::filesystem::create_directory(dir.path("a-much-longer-folder-name"));
    const auto source = ctLikeGrid();
    BaselineSettings settings[3] = {zfpAccuracy(2.0), withMethod(BaselineMethod::VdbBlosc),
                                    withMethod(BaselineMethod::Downsample)};
    settings[2].factor = 2;
    for (const BaselineSettings& s : settings) {
        const std::string near = dir.path("s"), far = dir.path("a-much-longer-folder-name/stream.bin");
        // Sizes, not bytes: every .vdb file carries a random UUID.
        EXPECT_EQ(runBaseline(*source, s, near).streamBytes, runBaseline(*source, s, far).streamBytes)
            << baselineMethodName(s.method);
    }
}

TEST(BaselineSettings, ValidationNamesTheSetting) {
    BaselineSettings s;
    EXPECT_NE(s.validate().find("`tolerance=T`"), std::string::npos);
    s.tolerance = 1.0;
    EXPECT_EQ(s.validate(), "");
    s.targetBytes = 100;
    EXPECT_NE(s.validate().find("not both"), std::string::npos);
    s = withMethod(BaselineMethod::Downsample);
    s.factor = 1;
    EXPECT_NE(s.validate().find("`factor`"), std::string::npos);
    s = withMethod(BaselineMethod::VdbBlosc);
    s.rate = 4.0;
    EXPECT_NE(s.validate().find("`rate`"), std::string::npos);
    EXPECT_THROW(parseBaselineMethod("jpeg"), InputError);
    for (const char* name : {"zfp-accuracy", "zfp-rate", "vdb-blosc", "vdb-half", "downsample"}) {
        EXPECT_EQ(baselineMethodName(parseBaselineMethod(name)), name);
    }
}

TEST(BaselineCli, JsonReportThenEvalAndRender) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string files = " -o '" + dir.path("r.vdb") + "' --stream '" + dir.path("s.zfp") + "'";
    const test::CommandResult run =
        test::runGvr("baseline -q '" + grid + "' --method zfp-accuracy --tolerance 0.5 --json" + files, dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    for (const char* key : {"method", "stream", "output", "bytes", "bits_per_voxel", "tolerance", "compress_s",
                            "decompress_s", "voxels", "channels"}) {
        EXPECT_TRUE(report.contains(key)) << key;
    }
    EXPECT_FALSE(report.contains("matched"));
    EXPECT_FALSE(report.contains("rate"));
    EXPECT_EQ(report["bytes"], std::filesystem::file_size(dir.path("s.zfp")));
    EXPECT_EQ(report["voxels"], 24 * 20 * 16);
    EXPECT_NEAR(report["bits_per_voxel"].get<double>(), 8.0 * report["bytes"].get<double>() / (24 * 20 * 16), 1e-9);

    const test::CommandResult eval = test::runGvr("eval --json '" + grid + "' '" + dir.path("r.vdb") + "'", dir);
    ASSERT_EQ(eval.exitCode, 0) << eval.err;
    EXPECT_GT(nlohmann::json::parse(eval.out)["psnr"].get<double>(), 50.0);  // 0.5 of a 200 range at worst
    const test::CommandResult render =
        test::runGvr("render '" + dir.path("r.vdb") + "' -o '" + dir.path("r.png") + "' --size 32x32", dir);
    EXPECT_EQ(render.exitCode, 0) << render.err;

    const test::CommandResult search =
        test::runGvr("baseline -q '" + grid + "' --method zfp-accuracy --target-bytes 2000 --json" + files, dir);
    ASSERT_EQ(search.exitCode, 0) << search.err;
    EXPECT_TRUE(nlohmann::json::parse(search.out).contains("matched"));
}

TEST(BaselineCli, BadInputIsOneLineExitTwoAndNoOutput) {
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    std::filesystem::create_directory(dir.path("out"));
    const std::string files = " -o '" + dir.path("out/r.vdb") + "' --stream '" + dir.path("out/s.bin") + "'";
    for (const std::string& arguments :
         {"baseline '" + grid + "' --method jpeg" + files,
          "baseline '" + grid + "' --method downsample --factor 0" + files,
          "baseline '" + grid + "' --method zfp-rate" + files, "baseline '" + grid + "' --method zfp-accuracy" + files,
          "baseline '" + grid + "' --method vdb-blosc --rate 4" + files,
          "baseline '" + grid + "' --method zfp-accuracy --tolerance -1" + files,
          "baseline '" + dir.path("missing.vdb") + "' --method vdb-half" + files,
          "baseline '" + grid + "' --method vdb-blosc -o '" + dir.path("out/x.vdb") + "' --stream '" +
              dir.path("out/x.vdb") + "'"}) {
        const test::CommandResult run = test::runGvr(arguments, dir);
        EXPECT_EQ(run.exitCode, 2) << arguments;
        EXPECT_EQ(test::lineCount(run.err), 1u) << arguments << "\n" << run.err;
        EXPECT_EQ(run.err.rfind("gvr: error: ", 0), 0u) << run.err;
        EXPECT_TRUE(std::filesystem::is_empty(dir.path("out"))) << arguments;
    }
}

}  // namespace
}  // namespace gvr
