// Volume outputs: the extension picks the format, outputs are checked before any
// work, and writing several is all or none.

#include "io/formats/GridFile.h"
#include "io/formats/Readers.h"
#include "io/formats/VolumeOutputs.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>

namespace gvr {
namespace {

std::size_t filesIn(const test::TempDir& dir) {
    return std::size_t(std::distance(std::filesystem::directory_iterator(dir.root()), {}));
}

TEST(VolumeOutputs, TheExtensionNamesTheFormatInAnyCase) {
    EXPECT_EQ(volumeFileFormat("a.vdb"), VolumeFileFormat::Vdb);
    EXPECT_EQ(volumeFileFormat("A.VDB"), VolumeFileFormat::Vdb);
    EXPECT_EQ(volumeFileFormat("x.nii"), VolumeFileFormat::Nifti);
    EXPECT_EQ(volumeFileFormat("x.NII.GZ"), VolumeFileFormat::Nifti);
    EXPECT_EQ(volumeFileFormat("folder.vdb/x.nii.gz"), VolumeFileFormat::Nifti);
    for (const std::string path : {"x.nii.bz2", "x.gz", "x", "x.vdb.tmp", "vdb", ""}) {
        const std::string message = test::errorMessageOf<InputError>([&] { volumeFileFormat(path); });
        EXPECT_EQ(message.rfind(path + ": unknown output extension", 0), 0u) << path << ": " << message;
    }
}

TEST(VolumeOutputs, OutputsAreCheckedBeforeAnyWork) {
    test::TempDir dir;
    const std::string vdb = dir.path("a.vdb"), nifti = dir.path("a.nii.gz");
    EXPECT_NO_THROW(checkVolumeOutputs("-o", {vdb, nifti}, {}));
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { checkVolumeOutputs("-o", {}, {}); }),
              "-o: an output file is required");
    const std::string twice = test::errorMessageOf<InputError>([&] {
        checkVolumeOutputs("-o", {vdb, dir.path("b.VDB")}, {});
    });
    EXPECT_EQ(twice.rfind("-o: two outputs of the same format (" + dir.path("b.VDB") + ")", 0), 0u) << twice;
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { checkVolumeOutputs("-o", {dir.path("missing/a.vdb")}, {}); }),
              "-o " + dir.path("missing/a.vdb") + ": output folder does not exist");
    const std::string unknown =
        test::errorMessageOf<InputError>([&] { checkVolumeOutputs("-o", {dir.path("a.raw")}, {}); });
    EXPECT_EQ(unknown.rfind(dir.path("a.raw") + ": unknown output extension", 0), 0u) << unknown;
    // Writing over the input would destroy it before it is read.
    const std::string input = dir.path("in.nii");
    test::writeBytes(input, "a volume");
    const std::string same = test::errorMessageOf<InputError>([&] { checkVolumeOutputs("-o", {input}, {input}); });
    EXPECT_EQ(same.rfind("-o " + input + ": is also an input", 0), 0u) << same;
    EXPECT_EQ(filesIn(dir), 1u);
}

TEST(VolumeOutputs, BothFormatsAreWrittenAndReadBack) {
    test::TempDir dir;
    const openvdb::GridBase::Ptr grid =
        test::makeGrid({4, 3, 2}, [](int i, int j, int k) { return float(1 + i + 10 * j + 100 * k); });
    const std::string vdb = dir.path("out.vdb"), nifti = dir.path("out.nii");
    const std::vector<WrittenVolume> written =
        writeVolumeOutputs({vdb, nifti}, {grid}, volumeBox(*grid), NiftiStorage{});
    ASSERT_EQ(written.size(), 2u);
    EXPECT_EQ(written[0].path, vdb);
    EXPECT_EQ(written[0].format, VolumeFileFormat::Vdb);
    EXPECT_EQ(written[0].fileBytes, std::filesystem::file_size(vdb));
    EXPECT_EQ(written[1].path, nifti);
    EXPECT_EQ(written[1].format, VolumeFileFormat::Nifti);
    EXPECT_EQ(written[1].fileBytes, std::filesystem::file_size(nifti));
    EXPECT_EQ(written[1].clampedSamples, 0u);
    EXPECT_EQ(filesIn(dir), 2u);  // no staged file left behind

    const openvdb::GridPtrVecPtr grids = readGridFile(vdb);
    ASSERT_EQ(grids->size(), 1u);
    EXPECT_EQ(grids->front()->activeVoxelCount(), grid->activeVoxelCount());

    const DenseVolume back = readNifti(nifti, ReadOptions{});
    ASSERT_EQ(back.dims, (std::array<std::int64_t, 3>{4, 3, 2}));
    ASSERT_EQ(back.type, SampleType::Float32);
    // Voxel (0, 0, 0) holds the minimum, which ingest makes background; the rest are exact.
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 4; ++i) {
                if (i + j + k == 0) continue;
                EXPECT_EQ(back.data<float>()[(k * 3 + j) * 4 + i], float(1 + i + 10 * j + 100 * k)) << i << j << k;
            }
        }
    }
}

TEST(VolumeOutputs, AFailedSecondOutputLeavesTheFirstAsItWas) {
    test::TempDir dir;
    // NIfTI takes float, double or vec3s grids only: an int32 grid fails after the .vdb is staged.
    const openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
    grid->tree().setValue(openvdb::Coord(1, 1, 1), 5);
    const std::string vdb = dir.path("out.vdb"), nifti = dir.path("out.nii");
    test::writeBytes(vdb, "the previous output");
    EXPECT_THROW(writeVolumeOutputs({vdb, nifti}, {grid}, grid->evalActiveVoxelBoundingBox(), NiftiStorage{}),
                 InputError);
    EXPECT_EQ(test::readBytes(vdb), "the previous output");
    EXPECT_FALSE(std::filesystem::exists(nifti));
    EXPECT_EQ(filesIn(dir), 1u);
}

}  // namespace
}  // namespace gvr
