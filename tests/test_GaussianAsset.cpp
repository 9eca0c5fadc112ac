// The asset file: round trip within quantisation error, budgets, and corrupt files.

#include "Error.h"
#include "GaussianAsset.h"
#include "GaussianField.h"
#include "TestHelpers.h"

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

TEST(GaussianAsset, RoundTripKeepsTheFieldWithinQuantisationError) {
    test::TempDir dir;
    for (int channels : {1, 3}) {
        GaussianAsset asset = randomAsset(2000, channels);
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
        const GaussianField a(original, 3.0f), b(back.params, 3.0f);
        std::mt19937 random(2);
        std::uniform_real_distribution<float> position(0.0f, 180.0f);
        std::vector<std::uint32_t> hits;
        double worst = 0.0;
        for (int q = 0; q < 3000; ++q) {
            const float x[3] = {position(random), position(random), position(random)};
            float va[3], vb[3];
            a.evaluate(x, va, hits);
            b.evaluate(x, vb, hits);
            for (int c = 0; c < channels; ++c) worst = std::max(worst, double(std::abs(va[c] - vb[c])));
        }
        EXPECT_LT(worst, 2e-2) << channels << " channels";
        // quantisedCopy() is exactly what the file gives back.
        EXPECT_EQ(quantisedCopy(original).values[kMeans], back.params.values[kMeans]);
    }
}

TEST(GaussianAsset, BudgetIsNeverExceeded) {
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

TEST(GaussianAsset, CorruptFilesAreRejected) {
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

TEST(GaussianAsset, EmptyAssetRoundTrips) {
    test::TempDir dir;
    GaussianAsset asset = randomAsset(0, 1);
    writeAsset(dir.path("empty.gvr"), asset);
    EXPECT_EQ(readAsset(dir.path("empty.gvr")).params.count(), 0u);
}

}  // namespace
}  // namespace gvr
