// The asset file: round trip within quantisation error, budgets, and corrupt files.

#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "pipeline/GaussianField.h"
#include "tests/TestHelpers.h"

#include <cstring>
#include <fstream>
#include <functional>
#include <random>

namespace gvr {
namespace {

GaussianAsset randomAsset(std::size_t count, int channels) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), position(0.0f, 180.0f);
    GaussianAsset asset;
    asset.params = GaussianParameters(count, channels);
    for (std::size_t i = 0; i < count; ++i) {
        for (int a = 0; a < 3; ++a) asset.params.at(kMeans, i)[a] = position(random);
        float* q = asset.params.at(kRotations, i);
        for (int k = 0; k < 4; ++k) q[k] = unit(random);
        const float norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int k = 0; k < 4; ++k) q[k] /= norm;
        for (int a = 0; a < 3; ++a) asset.params.at(kLogScales, i)[a] = 1.5f * unit(random);
        *asset.params.at(kOpacityLogits, i) = 3.0f * unit(random);
        for (int c = 0; c < channels; ++c) asset.params.at(kColours, i)[c] = unit(random);
    }
    asset.source.sourceType = "int16";
    asset.source.channels = channels;
    asset.source.dims = openvdb::Vec3i(181, 217, 181);
    asset.mapping.offset = {-1024.0, -1024.0, -1024.0};
    asset.mapping.scale = 3000.0;
    asset.worldFromIndex.setTranslation(openvdb::Vec3d(-90, -126, -72));
    return asset;
}

/// Largest and RMS difference of two fields at random points of the asset's box.
std::pair<double, double> fieldDifference(const GaussianParameters& p, const GaussianParameters& q, int channels) {
    const GaussianField a(p, 3.0f), b(q, 3.0f);
    std::mt19937 random(2);
    std::uniform_real_distribution<float> position(0.0f, 180.0f);
    std::vector<std::uint32_t> hits;
    double worst = 0.0, sumSquares = 0.0;
    constexpr int kPoints = 3000;
    for (int k = 0; k < kPoints; ++k) {
        const float x[3] = {position(random), position(random), position(random)};
        float va[3], vb[3];
        a.evaluate(x, va, hits);
        b.evaluate(x, vb, hits);
        for (int c = 0; c < channels; ++c) {
            worst = std::max(worst, double(std::abs(va[c] - vb[c])));
            sumSquares += double(va[c] - vb[c]) * (va[c] - vb[c]) / channels;
        }
    }
    return {worst, std::sqrt(sumSquares / kPoints)};
}

TEST(AssetFile, RoundTripKeepsTheFieldWithinQuantisationError) {
    test::TempDir dir;
    // The default bit depths were chosen on real fits (README); fine ones show the
    // codec itself loses nothing beyond its quantisers.
    AssetEncoding fine;
    fine.meanStep = 1.0f / 1024.0f;
    fine.rotationBits = 15;
    fine.logScaleBits = 16;
    fine.amplitudeBits = 16;
    for (int channels : {1, 3}) {
        for (const bool useFine : {false, true}) {
            GaussianAsset asset = randomAsset(2000, channels);
            if (useFine) asset.encoding = fine;
            const GaussianParameters original = asset.params;
            writeAsset(dir.path("a.gvr"), asset);
            const GaussianAsset back = readAsset(dir.path("a.gvr"));
            EXPECT_EQ(back.params.count(), 2000u);
            EXPECT_EQ(back.params.channels, channels);
            EXPECT_EQ(back.worldFromIndex, asset.worldFromIndex);
            EXPECT_EQ(back.mapping.scale, 3000.0);
            EXPECT_EQ(back.source.dims, asset.source.dims);
            EXPECT_EQ(std::filesystem::file_size(dir.path("a.gvr")), assetFileBytes(asset));
            // The field, not the parameters, is what matters: compare it at many points.
            const auto [worst, rms] = fieldDifference(original, back.params, channels);
            if (useFine) {
                EXPECT_LT(worst, 1e-3) << channels << " channels, fine encoding";
            } else {
                // Means on a 1/8-voxel lattice move a Gaussian 0.1 voxel at most; for the
                // thinnest here (sigma 0.22 voxel) that changes its value by up to a quarter
                // of its amplitude at one point, so the RMS is what the defaults answer for.
                EXPECT_LT(worst, 0.25) << channels << " channels, default encoding";
                EXPECT_LT(rms, 1.5e-3) << channels << " channels, default encoding";
            }
            // quantisedCopy() of the parameters in storage order is exactly what the file gives back.
            const GaussianParameters copy = quantisedCopy(asset.params, asset.encoding);
            for (int g = 0; g < kGroupCount; ++g) {
                EXPECT_EQ(copy.values[g], back.params.values[g]) << groupName(ParameterGroup(g));
            }
        }
    }
}

TEST(AssetFile, BudgetIsNeverExceeded) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(100, 1);
    const std::uint64_t budget = 1000;
    EXPECT_LT(assetCapacity(asset, budget), 100u);
    const std::size_t dropped = writeAsset(dir.path("small.gvr"), asset, budget);
    EXPECT_GT(dropped, 0u);
    EXPECT_LE(std::filesystem::file_size(dir.path("small.gvr")), budget);
    GaussianAsset roomy = randomAsset(10, 1);
    EXPECT_GE(assetCapacity(roomy, 1 << 20), 10u);
    EXPECT_EQ(writeAsset(dir.path("roomy.gvr"), roomy, 1 << 20), 0u);
}

TEST(AssetFile, CorruptFilesAreRejected) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(50, 1);
    writeAsset(dir.path("good.gvr"), asset);
    const std::string good = test::readBytes(dir.path("good.gvr"));

    std::string flipped = good;
    flipped[good.size() / 2] ^= 0x5a;
    test::writeBytes(dir.path("flipped.gvr"), flipped);
    EXPECT_THROW(readAsset(dir.path("flipped.gvr")), InputError);

    test::writeBytes(dir.path("cut.gvr"), good.substr(0, good.size() - 30));
    EXPECT_THROW(readAsset(dir.path("cut.gvr")), InputError);

    std::string future = good;
    future[8] = 9;  // version
    test::writeBytes(dir.path("future.gvr"), future);
    try {
        readAsset(dir.path("future.gvr"));
        FAIL() << "version 9 was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("unsupported asset version 9"), std::string::npos);
    }
    test::writeBytes(dir.path("other.gvr"), "GVRASSE");
    EXPECT_THROW(readAsset(dir.path("other.gvr")), InputError);
}

/// @a bytes with the header's count replaced, and the header length mended.
std::string withCount(const std::string& bytes, std::size_t count) {
    std::uint32_t headerBytes;
    std::memcpy(&headerBytes, bytes.data() + 12, 4);
    nlohmann::json header = nlohmann::json::parse(bytes.substr(16, headerBytes));
    header["count"] = count;
    const std::string text = header.dump();
    const auto length = std::uint32_t(text.size());
    std::string out = bytes.substr(0, 12);
    out.append(reinterpret_cast<const char*>(&length), 4);
    return out + text + bytes.substr(16 + headerBytes);
}

TEST(AssetFile, ValidButAbsurdNumbersAreRefused) {
    test::TempDir dir;
    const auto refusal = [&](GaussianAsset asset) {
        writeAsset(dir.path("odd.gvr"), asset);  // a well-formed file with a correct checksum
        try {
            readAsset(dir.path("odd.gvr"));
        } catch (const InputError& error) {
            return std::string(error.what());
        }
        return std::string("read without complaint");
    };
    for (float cutoff : {0.0f, -3.0f, 0.5f, 1e6f}) {
        GaussianAsset asset = randomAsset(20, 1);
        asset.cutoffSigmas = cutoff;
        EXPECT_NE(refusal(asset).find("cutoff"), std::string::npos) << cutoff;
    }
    GaussianAsset flat = randomAsset(20, 1);
    flat.worldFromIndex = openvdb::math::Mat4d::zero();
    flat.worldFromIndex(3, 3) = 1.0;
    EXPECT_NE(refusal(flat).find("singular"), std::string::npos);
    // Each of these once crashed render or exported +Inf.
    const auto refusalWith = [&](const std::function<void(GaussianAsset&)>& change) {
        GaussianAsset asset = randomAsset(20, 1);
        change(asset);
        return refusal(asset);
    };
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.mapping.scale = 1e308; }).find("value_scale"), std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.mapping.scale = -2.0; }).find("value_scale"), std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.mapping.offset[0] = -1e300; }).find("value_offset"),
              std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.worldFromIndex(0, 3) = 0.5; }).find("affine"), std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.worldFromIndex(3, 3) = 0.0; }).find("affine"), std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) {
                  a.worldFromIndex.setTranslation(openvdb::Vec3d(1e300, 0, 0));
              }).find("affine"),
              std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.params.at(kLogScales, 3)[1] = -30.0f; }).find("log-scale -30"),
              std::string::npos);
    EXPECT_NE(refusalWith([](GaussianAsset& a) { a.params.at(kMeans, 5)[2] = 1e9f; }).find("beyond any volume"),
              std::string::npos);
    // The extremes gvr itself writes still read.
    EXPECT_EQ(refusalWith([](GaussianAsset& a) {
                  a.mapping.scale = 1e-36;
                  a.mapping.offset = {3e38, 3e38, 3e38};
                  a.params.at(kLogScales, 0)[0] = kMinLogScale;
                  a.params.at(kLogScales, 1)[0] = kMaxLogScale;
              }),
              "read without complaint");
}

TEST(AssetFile, AHeaderNestedTooDeepIsRefusedBeforeParsing) {
    // nlohmann's parser recurses a level at a time: 100,000 levels overflowed the stack.
    test::TempDir dir;
    const std::string header = std::string(100000, '[') + std::string(100000, ']');
    std::string bytes("GVRASSET");
    const std::uint32_t version = 2, length = std::uint32_t(header.size());
    bytes.append(reinterpret_cast<const char*>(&version), 4);
    bytes.append(reinterpret_cast<const char*>(&length), 4);
    bytes += header + std::string(8, '\0');
    test::writeBytes(dir.path("deep.gvr"), bytes);
    try {
        readAsset(dir.path("deep.gvr"));
        FAIL() << "a header nested 100,000 deep was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("nested more than 64 deep"), std::string::npos) << error.what();
    }
}

TEST(AssetFile, ACountTheFileCannotHoldIsRefusedBeforeAllocating) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(50, 1);
    writeAsset(dir.path("good.gvr"), asset);
    test::writeBytes(dir.path("huge.gvr"), withCount(test::readBytes(dir.path("good.gvr")), std::size_t(1) << 30));
    try {
        readAsset(dir.path("huge.gvr"));
        FAIL() << "a count of 2^30 was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("impossible for a body"), std::string::npos) << error.what();
    }
}

TEST(AssetFile, ACompressedBodyMayNotExpandBeyondEightGaussiansAByte) {
    // A 257 KB file once decoded into 16.7 million Gaussians (2.1 GB).
    test::TempDir dir;
    GaussianAsset asset = randomAsset(50, 1);
    writeAsset(dir.path("good.gvr"), asset);
    const std::string good = test::readBytes(dir.path("good.gvr"));
    std::uint32_t headerBytes;
    std::memcpy(&headerBytes, good.data() + 12, 4);
    const std::size_t bodyBytes = good.size() - 16 - headerBytes - 4;
    test::writeBytes(dir.path("bomb.gvr"), withCount(good, 9 * bodyBytes));
    try {
        readAsset(dir.path("bomb.gvr"));
        FAIL() << "nine Gaussians a byte were accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("at most 8 Gaussians a byte"), std::string::npos) << error.what();
    }
}

TEST(AssetFile, StorageOrderKeepsLabelGroupsAndSortsInsideThem) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(300, 1);
    asset.labels.assign(300, 7);
    std::fill(asset.labels.begin(), asset.labels.begin() + 120, 3);
    asset.labelTable.names = {{3, "three"}, {7, "seven"}};
    writeAsset(dir.path("labelled.gvr"), asset);
    const GaussianAsset back = readAsset(dir.path("labelled.gvr"));
    ASSERT_EQ(back.labels.size(), 300u);
    EXPECT_EQ(std::count(back.labels.begin(), back.labels.begin() + 120, 3), 120);
    EXPECT_EQ(std::count(back.labels.begin() + 120, back.labels.end(), 7), 180);
    const QuantisationV2 quantisation(back.params, {});
    for (std::size_t i = 1; i < 300; ++i) {
        if (i == 120) continue;
        EXPECT_LE(quantisation.mortonCode(back.params.at(kMeans, i - 1)),
                  quantisation.mortonCode(back.params.at(kMeans, i)));
    }
}

TEST(AssetFile, Version1FilesStillLoad) {
    // Written by gvr before version 2, with the values that its `gvr probe` printed.
    const std::string path = std::string(GVR_TEST_DATA) + "/asset-v1-blobs.gvr";
    const GaussianAsset asset = readAsset(path);
    EXPECT_EQ(asset.formatVersion, 1u);
    ASSERT_EQ(asset.params.count(), 40u);
    const GaussianField field(asset.params, asset.cutoffSigmas);
    std::ifstream in(std::string(GVR_TEST_DATA) + "/asset-v1-blobs.probe.json");
    const nlohmann::json probe = nlohmann::json::parse(in);
    std::vector<std::uint32_t> hits;
    for (const nlohmann::json& point : probe.at("points")) {
        const auto index = point.at("index").get<std::array<float, 3>>();
        float value;
        field.evaluate(index.data(), &value, hits);
        const double physical = asset.mapping.offset[0] + asset.mapping.scale * value;
        EXPECT_NEAR(physical, point.at("value").get<double>(), 1e-3) << point.dump();
    }
}

TEST(AssetFile, EmptyAssetRoundTrips) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(0, 1);
    writeAsset(dir.path("empty.gvr"), asset);
    EXPECT_EQ(readAsset(dir.path("empty.gvr")).params.count(), 0u);
}

}  // namespace
}  // namespace gvr
