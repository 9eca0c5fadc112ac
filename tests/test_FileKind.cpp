// File kinds: content (the asset and OpenVDB magic numbers) wins over the name, the
// name decides the rest, and nothing that is not a regular file is opened.

#include "io/asset/AssetFile.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "tests/TestHelpers.h"

#include <sys/stat.h>

#include <fstream>

namespace gvr {
namespace {

void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

TEST(FileKind, MagicNumbersWinOverTheName) {
    test::TempDir dir;
    writeBytes(dir.path("scan.nii"), std::string(kAssetMagic, sizeof kAssetMagic) + "rest");
    EXPECT_EQ(fileKind(dir.path("scan.nii")), FileKind::Asset);
    initializeOpenVdb();
    writeGridFile(dir.path("picture.png"), {openvdb::FloatGrid::create()});
    EXPECT_EQ(fileKind(dir.path("picture.png")), FileKind::Vdb);
}

TEST(FileKind, TheNameDecidesFilesWithoutAMagicNumber) {
    test::TempDir dir;
    const std::pair<const char*, FileKind> cases[] = {{"a.nii", FileKind::Nifti},  {"a.NII.GZ", FileKind::Nifti},
                                                      {"a.mgz", FileKind::Mgh},    {"a.mhd", FileKind::MetaImage},
                                                      {"a.TIFF", FileKind::Image}, {"a.exr", FileKind::Image},
                                                      {"a.raw", FileKind::Other},  {"short.png", FileKind::Image}};
    for (const auto& [name, kind] : cases) {
        writeBytes(dir.path(name), std::string(name) == "short.png" ? "ab" : "not a magic number");
        EXPECT_EQ(fileKind(dir.path(name)), kind) << name;
        EXPECT_EQ(fileKindByName(name), kind) << name;
    }
}

TEST(FileKind, AVdbNameWithoutTheMagicIsNoVdb) {
    test::TempDir dir;
    writeBytes(dir.path("fake.vdb"), "plain text");
    EXPECT_EQ(fileKind(dir.path("fake.vdb")), FileKind::Other);
    EXPECT_EQ(fileKindByName("fake.vdb"), FileKind::Vdb);
}

TEST(FileKind, FoldersMissingFilesAndFifos) {
    test::TempDir dir;
    EXPECT_EQ(fileKind(dir.root().string()), FileKind::Folder);
    EXPECT_EQ(fileKind(dir.path("missing.nii")), FileKind::Other);
    ASSERT_EQ(mkfifo(dir.path("pipe.vdb").c_str(), 0600), 0);
    EXPECT_EQ(fileKind(dir.path("pipe.vdb")), FileKind::Other);  // returns: a FIFO is never opened
}

TEST(FileKind, OutputFormatsByExtensionInAnyCase) {
    EXPECT_EQ(outputFormat("a.vdb"), OutputFormat::Vdb);
    EXPECT_EQ(outputFormat("a.Nii.Gz"), OutputFormat::Nifti);
    EXPECT_EQ(outputFormat("frame.PNG"), OutputFormat::Png);
    EXPECT_EQ(outputFormat("frame.exr"), OutputFormat::Exr);
    EXPECT_EQ(outputFormat("folder.png/frame.jpg"), OutputFormat::Other);
}

}  // namespace
}  // namespace gvr
