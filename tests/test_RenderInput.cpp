// What render, view and Python draw: an asset or a grid read from a file, and the
// transfer function a name stands for.

#include "io/AssetFile.h"
#include "io/GridFile.h"
#include "io/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"
#include "workflow/FitToBudget.h"
#include "workflow/RenderInput.h"

#include "io/AssetExport.h"
#include "io/MemoryBudget.h"

#include <gtest/gtest.h>

#include <limits>

#include <cmath>

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
    const RenderInput asset = loadRenderInput(files.asset, "", "", 0.0f, {});
    ASSERT_TRUE(asset.asset.has_value());
    EXPECT_EQ(asset.asset->params.count(), 20u);
    EXPECT_NE(dynamic_cast<const GaussianRenderVolume*>(asset.volume.get()), nullptr);

    const RenderInput grid = loadRenderInput(files.grid, "", "", 0.0f, {});
    EXPECT_FALSE(grid.asset.has_value());
    EXPECT_NE(dynamic_cast<const GridRenderVolume*>(grid.volume.get()), nullptr);

    // Both renderers draw an asset's voxels: what its export holds, every reached voxel active.
    ExportSettings everything;
    everything.threshold = -std::numeric_limits<double>::infinity();
    const auto exported = openvdb::GridBase::grid<openvdb::FloatGrid>(exportAsset(*asset.asset, everything).grids.front());
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
    struct Ceiling {  // lifted again even when an assertion fails
        Ceiling() { setMemoryCeiling(4096); }  // the 16^3 float voxels need 16 KiB
        ~Ceiling() { setMemoryCeiling(0); }
    };
    std::string message;
    {
        const Ceiling ceiling;
        message = test::errorMessageOf<InputError>([&] { loadRenderInput(files.asset, "", "", 0.0f, {}); });
    }
    EXPECT_NE(message.find(files.asset + ": a volume of 16x16x16 voxels needs"), std::string::npos) << message;
    EXPECT_NE(message.find("to render"), std::string::npos) << message;
}

TEST(RenderInput, StructuresOfAGridAreRefusedNamingTheSetting) {
    const Files files;
    const std::string message = test::errorMessageOf<InputError>([&] { loadRenderInput(files.grid, "4", "", 0.0f, {}); });
    EXPECT_NE(message.find(files.grid), std::string::npos) << message;
    EXPECT_NE(message.find("`show` and `hide`"), std::string::npos) << message;
}

TEST(RenderInput, ATransferFunctionIsAFileWhenOneExistsElseAPreset) {
    const Files files;
    const RenderInput grid = loadRenderInput(files.grid, "", "", 0.0f, {});
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
