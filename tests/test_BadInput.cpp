// Broken input gets an InputError that names the file and the problem, never a
// crash or garbage. Corrupted copies of real data are made in a temporary folder.

#include "io/GridBuilder.h"
#include "io/Ingest.h"
#include "io/formats/GridFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <OpenImageIO/imageio.h>
#include <nifti2_io.h>
#include <sys/resource.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace gvr {
namespace {

/// Runs ingest on @a input and returns the error message, or fails the test.
std::string ingestError(const std::string& input, const IngestOptions& options = {}) {
    try {
        ingest(input, options);
    } catch (const InputError& error) {
        return error.what();
    }
    ADD_FAILURE() << "no InputError for " << input;
    return "";
}

void expectMentions(const std::string& message, const std::string& part) {
    EXPECT_NE(message.find(part), std::string::npos) << "message: " << message;
}

/// An uncompressed copy of ch2.nii.gz, for header surgery.
std::string plainCh2(const test::TempDir& dir) {
    const std::string path = dir.path("ch2.nii");
    nifti_image* image = nifti_image_read(test::sharedData("mri-colin27-aal/ch2.nii.gz").c_str(), 1);
    nifti_set_filenames(image, path.c_str(), 0, 0);
    nifti_image_write(image);
    nifti_image_free(image);
    return path;
}

std::string emptyFolder(const test::TempDir& dir, const std::string& name) {
    std::filesystem::create_directory(dir.path(name));
    return dir.path(name);
}

void patchInt16(const std::string& path, std::size_t offset, std::int16_t value) {
    std::string bytes = test::readBytes(path);
    std::memcpy(&bytes[offset], &value, sizeof value);
    test::writeBytes(path, bytes);
}

/// No sform or qform, so pixdim alone gives the voxel sizes.
void patchVoxelSizesWithoutOrientation(const std::string& path, const std::array<float, 3>& sizes) {
    patchInt16(path, 252, 0);  // qform_code
    patchInt16(path, 254, 0);  // sform_code
    std::string bytes = test::readBytes(path);
    std::memcpy(&bytes[80], sizes.data(), sizeof sizes);  // pixdim[1..3]
    test::writeBytes(path, bytes);
}

TEST(BadInput, TruncatedNifti) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string gz = dir.path("cut.nii.gz");
    test::copyTruncated(test::sharedData("mri-colin27-aal/ch2.nii.gz"), gz, 100000);
    expectMentions(ingestError(gz), gz + ": truncated");
    const std::string plain = plainCh2(dir);
    test::copyTruncated(plain, dir.path("cut.nii"), 352 + 1000);
    expectMentions(ingestError(dir.path("cut.nii")), "truncated");
}

TEST(BadInput, CorruptNiftiHeader) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    patchInt16(path, 0, 1234);  // sizeof_hdr
    expectMentions(ingestError(path), "corrupt NIfTI header");
}

TEST(BadInput, NiftiVoxOffsetThatCannotBeUsed) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    for (float offset : {-100.0f, 0.0f, 100.0f, 352.5f, std::nanf("")}) {
        const std::string path = plainCh2(dir);
        std::string bytes = test::readBytes(path);
        std::memcpy(&bytes[108], &offset, sizeof offset);  // vox_offset
        test::writeBytes(path, bytes);
        expectMentions(ingestError(path), "vox_offset");
    }
    // Beyond the end of the file: the samples are missing, not shifted.
    const std::string path = plainCh2(dir);
    std::string bytes = test::readBytes(path);
    const float far = 1e12f;
    std::memcpy(&bytes[108], &far, sizeof far);
    test::writeBytes(path, bytes);
    const std::string message = ingestError(path);
    EXPECT_TRUE(message.find("vox_offset") != std::string::npos || message.find("truncated") != std::string::npos)
        << message;
}

TEST(BadInput, NiftiSformWithAnInfiniteOffset) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    std::string bytes = test::readBytes(path);
    std::int16_t sformCode = 0;
    std::memcpy(&sformCode, &bytes[254], sizeof sformCode);
    if (sformCode == 0) {  // make the sform the one in use
        sformCode = 1;
        std::memcpy(&bytes[254], &sformCode, sizeof sformCode);
    }
    const float infinite = std::numeric_limits<float>::infinity();
    std::memcpy(&bytes[292], &infinite, sizeof infinite);  // srow_x[3], the x offset
    test::writeBytes(path, bytes);
    expectMentions(ingestError(path), "sform holds a value that is not finite");
}

// nifticlib replaces a voxel size of 0 or NaN with 1 mm; without an sform that
// guess would set every distance, so the user hears of it.
TEST(BadInput, NiftiVoxelSizeOfZeroOrNanIsAWarning) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    patchVoxelSizesWithoutOrientation(path, {1.0f, 0.0f, std::numeric_limits<float>::quiet_NaN()});
    const IngestResult result = ingest(path, {});
    std::string warnings;
    for (const std::string& warning : result.warnings) warnings += warning + "\n";
    expectMentions(warnings, "pixdim[2] is 0, not a voxel size: using 1 mm along axis y");
    expectMentions(warnings, "pixdim[3] is nan, not a voxel size");
    EXPECT_EQ(warnings.find("pixdim[1]"), std::string::npos) << warnings;
}

// Found by fuzz_nifti: OpenVDB refuses a transform whose determinant is below an
// absolute 3e-15, which micrometre-sized voxels given in millimetres reach.
TEST(BadInput, VoxelsTooSmallForOpenVdb) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    patchVoxelSizesWithoutOrientation(path, {1e-6f, 1e-6f, 1e-6f});
    expectMentions(ingestError(path), path + ": voxels too small for OpenVDB");
}

TEST(BadInput, DimensionsBeyondMemoryAreRefusedBeforeAllocating) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    for (std::size_t axis = 1; axis <= 3; ++axis) patchInt16(path, 40 + 2 * axis, 32000);
    expectMentions(ingestError(path), "to ingest, but only");
}

TEST(BadInput, UnsupportedNiftiDatatype) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    patchInt16(path, 70, NIFTI_TYPE_COMPLEX64);
    patchInt16(path, 72, 64);  // bitpix to match
    expectMentions(ingestError(path), "unsupported NIfTI datatype");
}

TEST(BadInput, NaNVoxelsAreCountedOrReplaced) {
    test::TempDir dir;
    std::vector<float> values(8, 1.0f);
    values[3] = std::numeric_limits<float>::quiet_NaN();
    values[5] = -std::numeric_limits<float>::infinity();
    test::writeBytes(dir.path("nan.raw"), test::rawBytes(values));
    IngestOptions options;
    options.read.raw = RawLayout{{2, 2, 2}, SampleType::Float32, 1, false, 0};
    expectMentions(ingestError(dir.path("nan.raw"), options), "2 voxels are NaN or Inf");
    options.build.nanTo = 0.0f;
    const IngestResult replaced = ingest(dir.path("nan.raw"), options);
    const auto stored = openvdb::gridConstPtrCast<openvdb::FloatGrid>(replaced.grid)->getConstAccessor();
    for (int n = 0; n < 8; ++n) {
        const openvdb::Coord ijk(n % 2, (n / 2) % 2, n / 4);
        EXPECT_EQ(stored.getValue(ijk), n == 3 || n == 5 ? 0.0f : 1.0f) << ijk;  // the two, and only they
    }
}

TEST(BadInput, StackSlicesOfDifferentSizes) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    std::filesystem::copy(test::sharedData("ct-head-visible-human-png/texture-0.png"), stack + "/0.png");
    std::filesystem::copy(test::sharedData("rgb-brainmaps54-cryosection/1020.jpg"), stack + "/1.jpg");
    expectMentions(ingestError(stack), "/1.jpg: slice is 512x304 but earlier slices are 512x512");
}

TEST(BadInput, TruncatedImageSlice) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    for (int slice = 0; slice < 3; ++slice) {
        const std::string name = "texture-" + std::to_string(slice) + ".png";
        std::filesystem::copy(test::sharedData("ct-head-visible-human-png/" + name), stack + "/" + name);
    }
    const std::string cut = stack + "/texture-1.png";
    test::copyTruncated(test::sharedData("ct-head-visible-human-png/texture-1.png"), cut, 4000);
    expectMentions(ingestError(stack), cut + ": truncated or corrupt PNG: chunk 'IDAT' runs past the end");
    test::copyTruncated(test::sharedData("ct-head-visible-human-png/texture-1.png"), cut,
                        std::filesystem::file_size(test::sharedData("ct-head-visible-human-png/texture-1.png")) - 12);
    expectMentions(ingestError(stack), cut + ": truncated PNG: it ends before its IEND chunk");
}

// libpng would notice a damaged IDAT only while decoding, through a longjmp that
// leaks inside OpenImageIO; every chunk carries a CRC-32 that is checked first.
TEST(BadInput, DamagedPngSlice) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    std::string bytes = test::readBytes(test::sharedData("ct-head-visible-human-png/texture-1.png"));
    bytes[bytes.size() / 2] ^= 0x5a;
    test::writeBytes(stack + "/texture-1.png", bytes);
    expectMentions(ingestError(stack), stack + "/texture-1.png: corrupt PNG: chunk 'IDAT' fails its CRC check");
}

TEST(BadInput, EmptyFolderAndMissingFile) {
    test::TempDir dir;
    std::filesystem::create_directory(dir.path("empty"));
    expectMentions(ingestError(dir.path("empty")), "folder is empty");
    expectMentions(ingestError(dir.path("nothing.nii")), "no such file or folder");
    expectMentions(ingestError(dir.path("*.png")), "pattern matches no files");
}

TEST(BadInput, TruncatedDicomSlice) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string series = emptyFolder(dir, "series");
    for (const char* name : {"1-001.dcm", "1-002.dcm", "1-003.dcm"}) {
        std::filesystem::copy(test::sharedData(std::string("ct-chest-ricord-512/") + name), series + "/" + name);
    }
    const std::string cut = series + "/1-002.dcm";
    test::copyTruncated(test::sharedData("ct-chest-ricord-512/1-002.dcm"), cut, 60000);
    expectMentions(ingestError(series), cut + ":");
}

TEST(BadInput, TruncatedMgzAndCorruptMghHeader) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string cut = dir.path("cut.mgz");
    test::copyTruncated(test::sharedData("mri-freesurfer-norm-aparc/norm.mgz"), cut, 300000);
    expectMentions(ingestError(cut), cut + ": truncated");
    test::writeBytes(dir.path("junk.mgh"), std::string(300, '\x7f'));
    expectMentions(ingestError(dir.path("junk.mgh")), "corrupt MGH header");
}

TEST(BadInput, CompressedDataThatFailsItsCrcIsRefused) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    for (const std::string source : {"mri-freesurfer-norm-aparc/norm.mgz", "mri-colin27-aal/ch2.nii.gz"}) {
        const std::string clean = test::readBytes(test::sharedData(source));
        for (double at : {0.3, 0.6, 0.9}) {
            std::string bytes = clean;
            bytes[std::size_t(at * double(bytes.size()))] ^= 0x5a;
            const std::string path = dir.path("flipped-" + std::to_string(int(at * 10)) +
                                              (source.find(".mgz") != std::string::npos ? ".mgz" : ".nii.gz"));
            test::writeBytes(path, bytes);
            expectMentions(ingestError(path), path + ": corrupt compressed data");
        }
    }
}

TEST(BadInput, AHeaderClaimingMoreThanTheFileHoldsCostsNoMemory) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string path = plainCh2(dir);
    for (std::size_t offset : {42u, 44u, 46u}) patchInt16(path, offset, 1600);  // dim[1..3]: 4.1 GB of uint8
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    expectMentions(ingestError(path), "truncated");
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 1L << 20) << "KiB of peak memory for a 7 MB file";
}

TEST(BadInput, TruncatedAndForeignVdb) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const IngestResult ingested = ingest(test::sharedData("mri-colin27-aal/ch2.nii.gz"), {});
    writeGridFile(dir.path("whole.vdb"), {ingested.grid});
    test::copyTruncated(dir.path("whole.vdb"), dir.path("cut.vdb"), 5000);
    expectMentions(ingestError(dir.path("cut.vdb")), dir.path("cut.vdb") + ":");
    test::writeBytes(dir.path("text.vdb"), "hello");
    expectMentions(ingestError(dir.path("text.vdb")), "not a VDB file");
}

TEST(BadInput, EveryCommandThatReadsAVdbRefusesNonFiniteValues) {
    // Once fit accepted them (and wrote an asset gvr could not read back) and render crashed.
    test::TempDir dir;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->denseFill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(15)), 1.0f, /*active=*/true);
    grid->tree().setValueOn(openvdb::Coord(3, 4, 5), NAN);
    writeGridFile(dir.path("nan.vdb"), {grid});
    const std::string in = "'" + dir.path("nan.vdb") + "' ";
    for (const std::string& command : {"fit " + in + "-o '" + dir.path("out.gvr") + "' --gaussians 20 --iterations 2",
                                       "render " + in + "-o '" + dir.path("out.png") + "'", "eval " + in + in,
                                       "baseline " + in + "--method zfp-accuracy --tolerance 0.1 -o '" +
                                           dir.path("out.vdb") + "' --stream '" + dir.path("out.zfp") + "'"}) {
        const test::CommandResult run = test::runGvr(command, dir);
        EXPECT_EQ(run.exitCode, 2) << command;
        EXPECT_EQ(test::lineCount(run.err), 1u) << command << ": " << run.err;
        EXPECT_NE(run.err.find("holds 1 NaN or infinite value"), std::string::npos) << command << ": " << run.err;
    }
    for (const char* output : {"out.gvr", "out.png", "out.vdb"})
        EXPECT_FALSE(std::filesystem::exists(dir.path(output)));
    // The fix the message names works.
    const test::CommandResult fixed =
        test::runGvr("ingest -q " + in + "--nan-to 0 -o '" + dir.path("fixed.vdb") + "'", dir);
    EXPECT_EQ(fixed.exitCode, 0) << fixed.err;
}

TEST(BadInput, MessagesNameTheRealProblem) {
    // NaN spacing once read as "voxels too small (1.38e-309)".
    DenseVolume volume = test::makeVolume<std::uint8_t>({2, 2, 2}, std::vector<std::uint8_t>(8, 1), SampleType::UInt8);
    volume.worldFromIndex(0, 0) = std::nan("");
    GridBuildSettings build;
    build.sourceFile = "nan-spacing.nii";
    const std::string nanSpacing = test::errorMessageOf<InputError>([&] { buildGrid(volume, build); });
    EXPECT_NE(nanSpacing.find("nan-spacing.nii: the voxel spacing or orientation is not a finite number"),
              std::string::npos)
        << "a NaN spacing gave: '" << nanSpacing << "'";
}

TEST(BadInput, AnOutputNameOfAnyValidLengthIsWritten) {
    // A 246-character name once failed: the temporary's prefix pushed it past 255.
    test::TempDir dir;
    const std::string grid = test::smallGrid(dir);
    const std::string name = dir.path(std::string(246 - 4, 'n') + ".gvr");
    const test::CommandResult run =
        test::runGvr("fit -q '" + grid + "' -o '" + name + "' --gaussians 20 --iterations 3", dir);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(std::filesystem::exists(name));
}

TEST(BadInput, AVdbWhoseActiveVoxelsSpanMoreThanAnIntIsRefused) {
    // What the fuzzer found: the box's extent overflowed int before any check.
    test::TempDir dir;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->tree().setValueOn(openvdb::Coord(-1707086569, 0, 0), 1.0f);
    grid->tree().setValueOn(openvdb::Coord(1953697792, 0, 0), 1.0f);
    writeGridFile(dir.path("far.vdb"), {grid});
    expectMentions(ingestError(dir.path("far.vdb")), "3660784362x1x1 are out of range");
}

TEST(BadInput, ATiffWhoseStripsClaimMoreRowsThanTheFileHoldsCostsNoMemory) {
    // What the fuzzer found: 10x12 pixels, but RowsPerStrip 1728053260, and
    // OpenImageIO sizes its strip buffer by the latter.
    const std::string file = std::string(GVR_TEST_DATA) + "/rows-per-strip-bomb.tif";
    expectMentions(ingestError(file), "truncated TIFF: page 2's directory at byte 196892 runs past the end");
    // Its one page alone (no pointer to a second) is refused for its strips.
    test::TempDir dir;
    std::string onePage = test::readBytes(file);
    onePage.replace(8 + 2 + 9 * 12, 4, std::string(4, '\0'));  // after the header, the count and 9 entries
    test::writeBytes(dir.path("one-page.tif"), onePage);
    expectMentions(ingestError(dir.path("one-page.tif")),
                   "10x12 pixels in strips of 1728053260 rows cannot come from a file of 413 bytes");
}

TEST(BadInput, RawFileShorterThanItsDimensions) {
    test::TempDir dir;
    test::writeBytes(dir.path("short.raw"), std::string(100, '\0'));
    IngestOptions options;
    options.read.raw = RawLayout{{10, 10, 10}, SampleType::UInt16, 1, false, 0};
    expectMentions(ingestError(dir.path("short.raw"), options), "truncated: voxel data needs 2000 bytes");
}

/// A PNG whose IHDR claims @a width x @a height, with a valid chunk CRC, so that
/// only the size gives it away.
std::string pngClaiming(const std::string& png, std::uint32_t width, std::uint32_t height) {
    std::string bytes = png;
    const auto putBigEndian = [&](std::size_t at, std::uint32_t value) {
        for (int b = 0; b < 4; ++b) bytes[at + b] = char((value >> (24 - 8 * b)) & 0xff);
    };
    putBigEndian(16, width);  // IHDR data starts after the signature, length and type
    putBigEndian(20, height);
    putBigEndian(29, std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data() + 12), 17)));
    return bytes;
}

TEST(BadInput, ImageHeadersClaimingHugeSlicesAreRefusedBeforeAllocating) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    const std::string png = test::readBytes(test::sharedData("ct-head-visible-human-png/texture-0.png"));
    for (int slice = 0; slice < 3; ++slice) {
        test::writeBytes(stack + "/" + std::to_string(slice) + ".png", pngClaiming(png, 30000, 30000));
    }
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    expectMentions(ingestError(stack), stack + "/0.png: corrupt image header: 30000x30000 pixels cannot come from");
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 100L << 10) << "KiB of peak memory for three small files";
}

/// A 10 x 12, 24-bit BMP with a 40-byte info header and @a compression.
std::string bmp(std::uint32_t compression) {
    const auto put32 = [](std::string& b, std::size_t at, std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b[at + i] = char((v >> (8 * i)) & 0xff);
    };
    const std::uint32_t rowBytes = 32, pixels = rowBytes * 12;
    std::string b(54 + pixels, '\0');
    b[0] = 'B';
    b[1] = 'M';
    put32(b, 2, std::uint32_t(b.size()));
    put32(b, 10, 54);
    put32(b, 14, 40);
    put32(b, 18, 10);
    put32(b, 22, 12);
    b[26] = 1;   // planes
    b[28] = 24;  // bits a pixel
    put32(b, 30, compression);
    put32(b, 34, pixels);
    for (std::size_t i = 54; i < b.size(); ++i) b[i] = char(i * 7);
    return b;
}

TEST(BadInput, CompressedOrCutBmpSlicesAreRefusedBeforeDecoding) {
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    test::writeBytes(stack + "/0.bmp", bmp(0));
    EXPECT_NO_THROW(ingest(stack, {}));  // the header the check reads is the one writers write

    // RLE4 on 24 bits: OpenImageIO's reader read before its buffer (fuzz_image).
    test::writeBytes(stack + "/0.bmp", bmp(2));
    expectMentions(ingestError(stack), stack + "/0.bmp: unsupported BMP: 24 bits a pixel with compression 2");
    test::writeBytes(stack + "/0.bmp", bmp(0).substr(0, 200));
    expectMentions(ingestError(stack), stack + "/0.bmp: truncated BMP: its pixels need 438 bytes, the file has 200");
}

/// A TIFF of @a pages pages of 64 x 64 noisy grey pixels, as OpenImageIO writes it.
void writeMultiPageTiff(const std::string& path, int pages) {
    auto output = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(output);
    const std::vector<OIIO::ImageSpec> specs(std::size_t(pages), OIIO::ImageSpec(64, 64, 1, OIIO::TypeDesc::UINT8));
    ASSERT_TRUE(output->open(path, pages, specs.data()));
    for (int page = 0; page < pages; ++page) {
        if (page > 0) {
            ASSERT_TRUE(output->open(path, specs[std::size_t(page)], OIIO::ImageOutput::AppendSubimage));
        }
        std::vector<std::uint8_t> pixels(64 * 64);
        for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = std::uint8_t((i * 2654435761u + page) >> 13);
        ASSERT_TRUE(output->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    }
    output->close();
}

// libtiff ends the page chain quietly at a directory past the end of the file, so
// OpenImageIO read a cut 5-page TIFF as 2 or 3 pages with no error.
TEST(BadInput, AMultiPageTiffCutShortIsRefused) {
    test::TempDir dir;
    writeMultiPageTiff(dir.path("whole.tif"), 5);
    EXPECT_EQ(readVolumeMetadata(*ingest(dir.path("whole.tif"), {}).grid)->dims[2], 5);
    const std::size_t size = std::filesystem::file_size(dir.path("whole.tif"));
    for (const double kept : {0.3, 0.5, 0.7, 0.99}) {
        test::copyTruncated(dir.path("whole.tif"), dir.path("cut.tif"), std::size_t(kept * double(size)));
        expectMentions(ingestError(dir.path("cut.tif")), dir.path("cut.tif") + ": truncated TIFF: page ");
    }
}

TEST(BadInput, TruncatedJpegSlice) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string stack = emptyFolder(dir, "stack");
    std::filesystem::copy(test::sharedData("rgb-brainmaps54-cryosection/1020.jpg"), stack + "/0.jpg");
    const std::string cut = stack + "/1.jpg";
    const std::size_t size = std::filesystem::file_size(test::sharedData("rgb-brainmaps54-cryosection/1020.jpg"));
    test::copyTruncated(test::sharedData("rgb-brainmaps54-cryosection/1020.jpg"), cut, size / 2);
    expectMentions(ingestError(stack), cut + ": truncated JPEG: no end-of-image marker");
}

TEST(BadInput, ADicomFileCutInsideItsHeader) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const std::string series = emptyFolder(dir, "series");
    for (std::size_t keep : {200u, 700u, 2000u}) {
        const std::string cut = series + "/cut.dcm";
        test::copyTruncated(test::sharedData("ct-chest-ricord-512/1-001.dcm"), cut, keep);
        expectMentions(ingestError(series), cut + ":");
    }
}

TEST(BadInput, TheMemoryCeilingIsHonouredAndNamedInTheMessage) {
    GVR_REQUIRE_SHARED_DATA();
    setMemoryCeiling(16u << 20);
    const std::string message = ingestError(test::sharedData("mri-colin27-aal/ch2.nii.gz"));
    setMemoryCeiling(0);
    expectMentions(message, "ch2.nii.gz: a volume of 181x217x181 voxels needs");
    expectMentions(message, "but only 0.0156 GiB is available");
    expectMentions(message, "NIfTI, MGH, MetaImage and VDB volumes are read whole");
    expectMentions(message, "image stacks and DICOM series are streamed");
}

TEST(BadInput, AStreamedVolumeIsRefusedWhenOneSlabDoesNotFit) {
    test::TempDir dir;
    test::writeBytes(dir.path("v.raw"), std::string(64 * 64 * 16, '\1'));
    IngestOptions options;
    options.read.raw = RawLayout{{64, 64, 16}, SampleType::UInt8, 1, false, 0};
    setMemoryCeiling(1024);
    const std::string message = ingestError(dir.path("v.raw"), options);
    setMemoryCeiling(0);
    expectMentions(message, "v.raw: one slab of 16 slices of 64x64 voxels needs");
}

}  // namespace
}  // namespace gvr
