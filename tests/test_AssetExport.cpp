// Export as the DCC tools and medical readers expect it: grid names, classes,
// metadata, derived densities (the NIfTI and transfer function writers: their own tests).

#include "io/asset/AssetExport.h"
#include "io/formats/GridFile.h"
#include "io/formats/NiftiWriter.h"
#include "io/formats/Readers.h"
#include "io/formats/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <nifti2_io.h>

#include <algorithm>
#include <cmath>

namespace gvr {
namespace {

GaussianAsset smallAsset(int channels) {
    GaussianAsset asset;
    asset.params = test::randomGaussians(120, channels, 20.0f, 9);
    asset.worldFromIndex.setToScale(openvdb::Vec3d(0.5, 0.5, 3.0));
    asset.worldFromIndex(0, 1) = 0.1;  // oblique
    asset.worldFromIndex.setTranslation(openvdb::Vec3d(-5.0, 2.0, 30.0));
    asset.mapping.offset = {-1024.0, -1024.0, -1024.0};
    asset.mapping.scale = 3000.0;
    asset.source.channels = channels;
    asset.source.dims = openvdb::Vec3i(22, 21, 20);
    asset.source.valueMin = -1024.0;
    asset.source.valueMax = 1976.0;
    asset.source.sourceType = "int16";
    return asset;
}

TEST(AssetExport, GreyBecomesADensityFogVolumeOnTheSourceGrid) {
    initializeOpenVdb();
    const GaussianAsset asset = smallAsset(1);
    const ExportResult result = exportAsset(asset, ExportSettings{});
    ASSERT_EQ(result.grids.size(), 1u);
    const auto& grid = *result.grids[0];
    EXPECT_EQ(grid.getName(), "density");
    EXPECT_EQ(grid.getGridClass(), openvdb::GRID_FOG_VOLUME);
    EXPECT_TRUE(grid.transform().baseMap()->getAffineMap()->getMat4().eq(asset.worldFromIndex));
    EXPECT_EQ(result.lattice.box.dim(), openvdb::Coord(22, 21, 20));
    EXPECT_EQ(result.threshold, -1024.0);  // no ingest threshold: the source minimum
    const auto metadata = readVolumeMetadata(grid);
    ASSERT_TRUE(metadata);
    EXPECT_EQ(metadata->dims, openvdb::Vec3i(22, 21, 20));
    EXPECT_EQ(metadata->sourceType, "int16");
    EXPECT_GT(grid.activeVoxelCount(), 0u);
}

TEST(AssetExport, DccStyleGivesOpacityAndColourInMetres) {
    initializeOpenVdb();
    const GaussianAsset asset = smallAsset(1);
    const ExportResult physical = exportAsset(asset, ExportSettings{});
    ExportSettings settings;
    settings.dcc = DccStyle{TransferFunction({{-500.0, {0, 0, 1, 0}}, {1000.0, {1, 0, 0, 0.8f}}}, "test")};
    const ExportResult result = exportAsset(asset, settings);
    ASSERT_EQ(result.grids.size(), 2u);
    const auto density = openvdb::GridBase::grid<openvdb::FloatGrid>(result.grids[0]);
    const auto colour = openvdb::GridBase::grid<openvdb::Vec3SGrid>(result.grids[1]);
    ASSERT_TRUE(density && colour);
    EXPECT_EQ(density->getName(), "density");
    EXPECT_EQ(colour->getName(), "color");
    EXPECT_EQ(density->getGridClass(), openvdb::GRID_FOG_VOLUME);
    EXPECT_TRUE(density->transform().baseMap()->getAffineMap()->getMat4().eq(
        asset.worldFromIndex * openvdb::math::scale<openvdb::Mat4d>(openvdb::Vec3d(1e-3))));
    // Every voxel as the transfer function maps its physical value; transparent ones left out.
    const auto values = openvdb::GridBase::grid<openvdb::FloatGrid>(physical.grids[0])->getConstAccessor();
    std::size_t checked = 0;
    for (auto voxel = density->cbeginValueOn(); voxel; ++voxel, ++checked) {
        const std::array<float, 4> rgba = settings.dcc->transfer(values.getValue(voxel.getCoord()));
        ASSERT_GT(*voxel, 0.0f);
        ASSERT_LE(*voxel, 1.0f);
        ASSERT_FLOAT_EQ(*voxel, rgba[3]);
        ASSERT_FLOAT_EQ(colour->tree().getValue(voxel.getCoord())[0], rgba[0]);
    }
    EXPECT_GT(checked, 0u);
    EXPECT_LT(density->activeVoxelCount(), physical.grids[0]->activeVoxelCount());  // values below -500 are transparent
    // What a material needs, for a user who sets it up by hand.
    const openvdb::Vec3d spacingM = axisSpacing(asset.worldFromIndex) * 1e-3;
    const openvdb::Vec3d extentM = spacingM * openvdb::Vec3d(asset.source.dims);
    for (const auto& grid : result.grids) {
        EXPECT_DOUBLE_EQ(grid->metaValue<double>("gvr_density_scale"),
                         1.0 / std::min({spacingM[0], spacingM[1], spacingM[2]}));
        EXPECT_DOUBLE_EQ(grid->metaValue<double>("gvr_object_size_m"), std::max({extentM[0], extentM[1], extentM[2]}));
    }
}

/// A cryosection in miniature: bright paper everywhere, a dark specimen in the middle.
GaussianAsset paperAndSpecimen() {
    GaussianAsset asset = smallAsset(3);
    asset.params = GaussianParameters(2, 3);
    const float means[2] = {10.0f, 10.0f}, scales[2] = {40.0f, 3.0f}, colours[2] = {0.8f, -0.6f};
    for (std::size_t g = 0; g < 2; ++g) {
        for (int a = 0; a < 3; ++a) asset.params.at(kMeans, g)[a] = means[g];
        asset.params.at(kRotations, g)[0] = 1.0f;
        for (int a = 0; a < 3; ++a) asset.params.at(kLogScales, g)[a] = std::log(scales[g]);
        *asset.params.at(kOpacityLogits, g) = 12.0f;
        for (int c = 0; c < 3; ++c) asset.params.at(kColours, g)[c] = colours[g];
    }
    return asset;
}

TEST(AssetExport, RgbGetsColourAndADerivedDensity) {
    initializeOpenVdb();
    const GaussianAsset asset = paperAndSpecimen();
    ExportSettings settings;
    settings.naming = GridNaming::Houdini;
    const ExportResult result = exportAsset(asset, settings);
    ASSERT_EQ(result.grids.size(), 2u);
    EXPECT_EQ(result.grids[0]->getName(), "Cd");
    EXPECT_EQ(result.grids[1]->getName(), "density");
    EXPECT_EQ(result.grids[1]->getGridClass(), openvdb::GRID_FOG_VOLUME);
    const auto colour = openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(result.grids[0]);
    const auto density = openvdb::gridConstPtrCast<openvdb::FloatGrid>(result.grids[1]);
    ASSERT_TRUE(colour && density);
    EXPECT_EQ(colour->activeVoxelCount(), density->activeVoxelCount());
    // The paper is what surrounds the specimen: it is thin, the specimen dense.
    const float paper = density->tree().getValue(openvdb::Coord(0, 0, 0));
    const float specimen = density->tree().getValue(openvdb::Coord(10, 10, 10));
    EXPECT_LT(paper, 0.05f);
    EXPECT_GT(specimen, 0.3f);
    // With a transfer function, density is its opacity at the luminance.
    settings.densityFrom = TransferFunction({{-1024.0, {0, 0, 0, 0.5f}}, {1976.0, {1, 1, 1, 0.0f}}}, "test");
    const auto ramp = openvdb::gridConstPtrCast<openvdb::FloatGrid>(exportAsset(asset, settings).grids[1]);
    for (auto voxel = colour->cbeginValueOn(); voxel; ++voxel) {
        const double lum = 0.2126 * (*voxel)[0] + 0.7152 * (*voxel)[1] + 0.0722 * (*voxel)[2];
        ASSERT_NEAR(ramp->tree().getValue(voxel.getCoord()), (*settings.densityFrom)(lum)[3], 1e-6);
    }
}

TEST(AssetExport, DensityFromIsRefusedForGreyAssets) {
    ExportSettings settings;
    settings.densityFrom = TransferFunction({{0.0, {0, 0, 0, 1}}}, "test");
    EXPECT_THROW(exportAsset(smallAsset(1), settings), InputError);
}

TEST(AssetExport, LatticeLikeAnotherGridStartsAtZero) {
    initializeOpenVdb();
    test::TempDir dir;
    auto other = openvdb::FloatGrid::create(0.0f);
    other->setName("density");
    other->setTransform(openvdb::math::Transform::createLinearTransform(2.0));
    other->tree().setValue(openvdb::Coord(10, 20, 30), 1.0f);
    other->tree().setValue(openvdb::Coord(13, 21, 35), 1.0f);
    writeGridFile(dir.path("other.vdb"), {other});
    const Lattice lattice = latticeLike(dir.path("other.vdb"));
    EXPECT_EQ(lattice.box, openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(3, 1, 5)));
    EXPECT_TRUE(lattice.worldFromIndex.transform(openvdb::Vec3d(0.0)).eq(openvdb::Vec3d(20.0, 40.0, 60.0)));
}

}  // namespace
}  // namespace gvr
