// What render, view and Python draw: an asset or a grid read from a file, and the
// transfer function a name stands for.

#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "io/formats/TransferFunctionFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "render/Camera.h"
#include "tests/TestHelpers.h"
#include "workflow/FitToBudget.h"
#include "workflow/RenderInput.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace gvr {
namespace {

openvdb::GridBase::Ptr ball() {
    return test::makeGrid({16, 16, 16}, [](int i, int j, int k) {
        const double r2 = (i - 8.0) * (i - 8.0) + (j - 8.0) * (j - 8.0) + (k - 8.0) * (k - 8.0);
        return float(10.0 + 100.0 * std::exp(-r2 / 20.0));
    });
}

struct Files {
    test::TempDir dir;
    std::string grid = dir.path("ball.vdb"), asset = dir.path("ball.gvr");
    Files() {
        writeGridFile(grid, {ball()});
        BudgetedFitOptions options;
        options.gaussians = 20;
        options.settings.seconds = 0.0;
        options.settings.iterations = 3;
        GaussianAsset fitted = fitToBudget(ball(), "ball", options).asset;
        writeAsset(asset, fitted);
    }
};

TEST(RenderInput, AnAssetIsItsGaussiansAndAGridItsVoxels) {
    const Files files;
    const RenderInput asset = loadRenderInput(files.asset, "", "", AssetLayers::All, 0.0f, {});
    ASSERT_TRUE(asset.asset.has_value());
    EXPECT_EQ(asset.asset->params.count(), 20u);
    EXPECT_NE(dynamic_cast<const GaussianRenderVolume*>(asset.volume.get()), nullptr);

    const RenderInput grid = loadRenderInput(files.grid, "", "", AssetLayers::All, 0.0f, {});
    EXPECT_FALSE(grid.asset.has_value());
    EXPECT_NE(dynamic_cast<const GridRenderVolume*>(grid.volume.get()), nullptr);

    // Both renderers draw an asset's voxels: what its export holds, every reached voxel active.
    ExportSettings everything;
    everything.threshold = -std::numeric_limits<double>::infinity();
    const auto exported =
        openvdb::GridBase::grid<openvdb::FloatGrid>(exportAsset(*asset.asset, everything).grids.front());
    const auto& voxels = dynamic_cast<const openvdb::FloatGrid&>(asset.volume->voxels());
    EXPECT_EQ(voxels.transform(), exported->transform());
    EXPECT_NEAR(double(voxels.activeVoxelCount()), double(exported->activeVoxelCount()), 8.0);
    ASSERT_GT(exported->activeVoxelCount(), 100u);
    const auto drawn = voxels.getConstAccessor();
    const auto reference = exported->getConstAccessor();
    float range = 0.0f;
    for (auto v = exported->cbeginValueOn(); v; ++v) range = std::max(range, std::abs(*v - exported->background()));
    for (auto ijk = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)).begin(); ijk; ++ijk) {
        EXPECT_NEAR(drawn.getValue(*ijk), reference.getValue(*ijk), 1e-5f * range) << *ijk;
    }
}

// An asset is drawn from its voxels: one whose source would not fit in memory is
// refused before anything is allocated, naming the file.
TEST(RenderInput, AnAssetWhoseVoxelsWouldNotFitIsRefused) {
    const Files files;
    struct Ceiling {                           // lifted again even when an assertion fails
        Ceiling() { setMemoryCeiling(4096); }  // the 16^3 float voxels need 16 KiB
        ~Ceiling() { setMemoryCeiling(0); }
    };
    std::string message;
    {
        const Ceiling ceiling;
        message =
            test::errorMessageOf<InputError>([&] { loadRenderInput(files.asset, "", "", AssetLayers::All, 0.0f, {}); });
    }
    EXPECT_NE(message.find(files.asset + ": a volume of 16x16x16 voxels needs"), std::string::npos) << message;
    EXPECT_NE(message.find("to render"), std::string::npos) << message;
}

/// The mean difference of two images' premultiplied channels.
double meanDifference(const Framebuffer& a, const Framebuffer& b) {
    double sum = 0.0;
    for (std::size_t n = 0; n < a.rgba.size(); ++n) sum += std::abs(a.rgba[n] - b.rgba[n]);
    return sum / double(a.rgba.size());
}

Framebuffer drawn(const RenderVolume& volume, const Classifier& classifier) {
    const OrthoCamera camera = makeCamera({30.0, 15.0}, worldCorners(volume.worldFromIndex(), volume.box()), 64, 64);
    return ShearWarpRenderer(volume, classifier, ShearWarpSettings{}).render(camera);
}

// A bounded asset is drawn from its reconstruction, cut as ingest cut its source:
// the source's own image up to the bound, where its Gaussians alone are a preview.
TEST(RenderInput, ABoundedAssetIsDrawnAsItsSourceUpToTheBound) {
    const openvdb::GridBase::Ptr source = test::makeGrid(
        {16, 16, 16},
        [](int i, int j, int k) {
            const double r2 = (i - 8.0) * (i - 8.0) + (j - 6.0) * (j - 6.0) + (k - 9.0) * (k - 9.0);
            return float(100.0 * std::exp(-r2 / 12.0) + ((i + 2 * j + 3 * k) % 5));  // a ball on a ridged floor
        },
        openvdb::Vec3d(1.0), /*threshold=*/3.5);
    const GaussianAsset asset = test::boundedAsset(source, 6, 0.25);
    const std::unique_ptr<RenderVolume> bounded = assetRenderVolume(asset, AssetLayers::All, 0.0f, "asset");
    const std::unique_ptr<RenderVolume> preview = assetRenderVolume(asset, AssetLayers::Gaussians, 0.0f, "asset");
    EXPECT_NE(dynamic_cast<const GaussianRenderVolume*>(preview.get()), nullptr);

    const auto& voxels = dynamic_cast<const openvdb::FloatGrid&>(bounded->voxels());
    const auto& original = dynamic_cast<const openvdb::FloatGrid&>(*source);
    // Drawn with the source's threshold again: only voxels within the bound of it may change side.
    const auto drawnValues = voxels.getConstAccessor();
    for (auto v = original.cbeginValueOn(); v; ++v) {
        if (*v < 3.5f + 0.25f) continue;
        EXPECT_TRUE(drawnValues.isValueOn(v.getCoord())) << v.getCoord();
        EXPECT_NEAR(drawnValues.getValue(v.getCoord()), *v, 0.25) << v.getCoord();
    }
    EXPECT_NEAR(double(voxels.activeVoxelCount()), double(original.activeVoxelCount()),
                0.05 * original.activeVoxelCount());

    const GridRenderVolume sourceVolume(source);
    const Classifier classifier = classifierFor("mri", sourceVolume);
    const Framebuffer truth = drawn(sourceVolume, classifier);
    const double boundedOff = meanDifference(drawn(*bounded, classifier), truth);
    const double previewOff = meanDifference(drawn(*preview, classifier), truth);
    EXPECT_LT(boundedOff, 0.002);
    EXPECT_LT(boundedOff * 10.0, previewOff) << "six Gaussians in three iterations are no copy of the ball";
}

TEST(RenderInput, StructuresOfAGridAreRefusedNamingTheSetting) {
    const Files files;
    const std::string message =
        test::errorMessageOf<InputError>([&] { loadRenderInput(files.grid, "4", "", AssetLayers::All, 0.0f, {}); });
    EXPECT_NE(message.find(files.grid), std::string::npos) << message;
    EXPECT_NE(message.find("`show` and `hide`"), std::string::npos) << message;
}

TEST(RenderInput, ATransferFunctionIsAFileWhenOneExistsElseAPreset) {
    const Files files;
    const RenderInput grid = loadRenderInput(files.grid, "", "", AssetLayers::All, 0.0f, {});
    const std::string path = files.dir.path("tf.json");
    writeTransferFunction(path, TransferFunction({{0, {0, 0, 0, 0}}, {50, {1, 0, 0, 0.5f}}}, "tf"));
    EXPECT_EQ(transferFunctionFor(path, *grid.volume).points().size(), 2u);
    EXPECT_FLOAT_EQ(transferFunctionFor(path, *grid.volume)(50.0)[3], 0.5f);
    std::string mismatch;
    const TransferFunction preset = transferFunctionFor("ct", *grid.volume, &mismatch);
    EXPECT_GT(preset.points().size(), 2u);
    EXPECT_NE(mismatch.find("mri fits them"), std::string::npos) << mismatch;  // no HU in these data
    EXPECT_THROW(transferFunctionFor(files.dir.path("missing.json"), *grid.volume), InputError);
}

}  // namespace
}  // namespace gvr
