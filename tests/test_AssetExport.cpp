// Export as the DCC tools and medical readers expect it: grid names, classes,
// metadata, derived densities, NIfTI geometry, transfer function files.

#include "io/AssetExport.h"
#include "io/GridFile.h"
#include "io/NiftiWriter.h"
#include "io/Readers.h"
#include "io/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <nifti2_io.h>

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
    EXPECT_TRUE(density->transform().baseMap()->getAffineMap()->getMat4().eq(asset.worldFromIndex *
                                                                               openvdb::math::scale<openvdb::Mat4d>(openvdb::Vec3d(1e-3))));
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

TEST(NiftiWriter, RoundTripsValuesAndAnObliqueAffine) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(5, 4, 3), 1);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = float(n) * 1.5f - 20.0f;
    volume.worldFromIndex = smallAsset(1).worldFromIndex;
    const std::string path = dir.path("out.nii.gz");
    writeNifti(path, volume);
    const DenseVolume back = readNifti(path, ReadOptions{});
    ASSERT_EQ(back.dims, (std::array<std::int64_t, 3>{5, 4, 3}));
    ASSERT_EQ(back.type, SampleType::Float32);
    for (std::size_t n = 0; n < volume.values.size(); ++n) ASSERT_EQ(back.data<float>()[n], volume.values[n]);
    EXPECT_TRUE(back.worldFromIndex.eq(volume.worldFromIndex, 1e-6));
    // Only the file itself is left in the folder: no temporary.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.root()), {}), 1);
}

TEST(NiftiWriter, RgbBecomesRgb24) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(3, 2, 2), 3);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = float(n * 23) - 10.0f;
    writeNifti(dir.path("rgb.nii"), volume);
    const DenseVolume back = readNifti(dir.path("rgb.nii"), ReadOptions{});
    ASSERT_EQ(back.channels, 3);
    for (std::size_t n = 0; n < volume.values.size(); ++n) {
        ASSERT_EQ(back.data<std::uint8_t>()[n], std::clamp(std::lround(volume.values[n]), 0L, 255L));
    }
}

TEST(NiftiWriter, KeepsTheSourcesDatatypeScalingAndCodes) {
    test::TempDir dir;
    FloatVolume volume(openvdb::Coord(4, 3, 2), 1);
    for (std::size_t n = 0; n < volume.values.size(); ++n) volume.values[n] = -1024.0f + float(n) * 50.3f;
    volume.values[0] = -3000.0f;  // below what uint8 with this scaling holds
    volume.values[1] = 5000.0f;   // above it
    NiftiStorage storage;
    storage.type = SampleType::UInt8;
    storage.slope = 7.1;
    storage.intercept = -1024.0;
    storage.codes = NiftiCodes{2, 2, NIFTI_UNITS_MM | NIFTI_UNITS_SEC};
    const std::string path = dir.path("out.nii.gz");
    EXPECT_EQ(writeNifti(path, volume, storage), 2u);

    const DenseVolume back = readNifti(path, ReadOptions{});
    ASSERT_EQ(back.type, SampleType::UInt8);
    EXPECT_NEAR(back.slope, 7.1, 1e-6);
    EXPECT_EQ(back.intercept, -1024.0);
    ASSERT_TRUE(back.niftiCodes);
    EXPECT_EQ(back.niftiCodes->sform, 2);
    EXPECT_EQ(back.niftiCodes->qform, 2);
    EXPECT_EQ(back.niftiCodes->xyztUnits, NIFTI_UNITS_MM | NIFTI_UNITS_SEC);
    EXPECT_EQ(back.data<std::uint8_t>()[0], 0);
    EXPECT_EQ(back.data<std::uint8_t>()[1], 255);
    for (std::size_t n = 2; n < volume.values.size(); ++n) {
        const double physical = back.slope * back.data<std::uint8_t>()[n] + back.intercept;
        ASSERT_LE(std::abs(physical - volume.values[n]), 7.1 / 2 + 1e-3) << n;
    }
}

TEST(NiftiWriter, StorageFollowsTheSourceOrSaysWhyItIsFloat32) {
    VolumeMetadata source;
    source.sourceType = "int16";
    source.storedSlope = 0.5;
    source.storedIntercept = -10.0;
    source.niftiCodes = NiftiCodes{4, 0, 10};
    const NiftiStorage kept = niftiStorageLike(source, false);
    EXPECT_EQ(kept.type, SampleType::Int16);
    EXPECT_EQ(kept.slope, 0.5);
    EXPECT_EQ(kept.intercept, -10.0);
    EXPECT_EQ(kept.codes.sform, 4);
    EXPECT_EQ(kept.codes.qform, 0);
    EXPECT_TRUE(kept.float32Reason.empty());

    const NiftiStorage asked = niftiStorageLike(source, true);
    EXPECT_EQ(asked.type, SampleType::Float32);
    EXPECT_EQ(asked.slope, 1.0);
    EXPECT_EQ(asked.codes.sform, 4);  // the codes survive --float32

    source.sourceType = "float64";
    EXPECT_EQ(niftiStorageLike(source, false).type, SampleType::Float32);
    EXPECT_NE(niftiStorageLike(source, false).float32Reason.find("float64"), std::string::npos);
    source.sourceType = "uint8";
    source.storedSlope = 0.0;
    EXPECT_EQ(niftiStorageLike(source, false).type, SampleType::Float32);
    EXPECT_FALSE(niftiStorageLike(source, false).float32Reason.empty());

    source.niftiCodes = NiftiCodes{7, 1, 2};  // not a NIfTI code: scanner and mm instead
    EXPECT_EQ(niftiStorageLike(source, false).codes.sform, 1);
    EXPECT_EQ(niftiStorageLike(VolumeMetadata{}, false).codes.qform, 1);  // not from NIfTI
}

TEST(NiftiWriter, AMissingFolderLeavesNothing) {
    test::TempDir dir;
    EXPECT_THROW(writeNifti(dir.path("missing/out.nii.gz"), FloatVolume(openvdb::Coord(2), 1)), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.path("missing")));
}

TEST(TransferFunctionFile, ReadsPointsAndRejectsBadOnes) {
    test::TempDir dir;
    test::writeBytes(dir.path("ok.json"), R"({"points": [[-100, 0, 0, 0, 0], [100, 1, 0.5, 0.25, 1]]})");
    const TransferFunction tf = readTransferFunction(dir.path("ok.json"));
    const auto middle = tf(0.0);
    EXPECT_FLOAT_EQ(middle[0], 0.5f);
    EXPECT_FLOAT_EQ(middle[1], 0.25f);
    EXPECT_FLOAT_EQ(middle[3], 0.5f);
    EXPECT_EQ(tf(-1e9)[3], 0.0f);
    EXPECT_EQ(tf(1e9)[3], 1.0f);
    const std::pair<const char*, const char*> bad[] = {
        {"notjson.json", "{points"},
        {"empty.json", R"({"points": []})"},
        {"short.json", R"({"points": [[0, 1, 1, 1]]})"},
        {"order.json", R"({"points": [[5, 0, 0, 0, 0], [5, 1, 1, 1, 1]]})"},
        {"range.json", R"({"points": [[0, 0, 0, 0, 1.5]]})"},
    };
    for (const auto& [name, text] : bad) {
        test::writeBytes(dir.path(name), text);
        try {
            readTransferFunction(dir.path(name));
            ADD_FAILURE() << name << " was accepted";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
        }
    }
}

}  // namespace
}  // namespace gvr
