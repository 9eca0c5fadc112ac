// Each reader on small files written here, with values and geometry known exactly.

#include "io/formats/Readers.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <OpenImageIO/imageio.h>
#include <nifti2_io.h>
#include <zlib.h>

#include <algorithm>
#include <tuple>

namespace gvr {
namespace {

template <typename T>
void appendWord(std::string& bytes, T value, bool bigEndian) {
    unsigned char word[sizeof(T)];
    std::memcpy(word, &value, sizeof(T));
    if (bigEndian != hostIsBigEndian()) swapBytes(word, 1, sizeof(T));
    bytes.append(reinterpret_cast<const char*>(word), sizeof(T));
}

openvdb::Vec3d worldOf(const DenseVolume& volume, openvdb::Vec3d index) {
    return volume.worldFromIndex.transform(index);
}

void expectNear(const openvdb::Vec3d& a, const openvdb::Vec3d& b) {
    EXPECT_NEAR(a.x(), b.x(), 1e-5);
    EXPECT_NEAR(a.y(), b.y(), 1e-5);
    EXPECT_NEAR(a.z(), b.z(), 1e-5);
}

TEST(RawReader, ReadsBigEndianSignedAfterAHeader) {
    test::TempDir dir;
    std::string bytes(16, 'x');
    const std::vector<std::int16_t> values{-1024, -1, 0, 1, 3071, 7};
    for (auto v : values) appendWord(bytes, v, true);
    test::writeBytes(dir.path("ct.raw"), bytes);
    ReadOptions options;
    options.raw = RawLayout{{3, 2, 1}, SampleType::Int16, 1, true, 16};
    options.spacingMm = openvdb::Vec3d(0.5, 0.5, 2.0);
    const DenseVolume volume = readVolume(dir.path("ct.raw"), options);
    for (std::size_t v = 0; v < values.size(); ++v) EXPECT_EQ(volume.data<std::int16_t>()[v], values[v]);
    expectNear(worldOf(volume, {1, 1, 1}), {0.5, 0.5, 2.0});
    EXPECT_TRUE(volume.warnings.empty());
}

TEST(RawReader, ASlabIsItsSlicesOfTheWholeVolume) {
    test::TempDir dir;
    std::string bytes;
    for (int v = 0; v < 3 * 2 * 5; ++v) appendWord(bytes, std::uint16_t(1000 + v), true);
    test::writeBytes(dir.path("v.raw"), bytes);
    ReadOptions options;
    options.raw = RawLayout{{3, 2, 5}, SampleType::UInt16, 1, true, 0};
    const auto source = openSliceSource(dir.path("v.raw"), options);
    ASSERT_TRUE(source);
    DenseVolume slab;
    source->readSlab(2, 3, slab);
    ASSERT_EQ(slab.dims, (std::array<std::int64_t, 3>{3, 2, 3}));
    for (int v = 0; v < 3 * 2 * 3; ++v) EXPECT_EQ(slab.data<std::uint16_t>()[v], 1000 + 2 * 3 * 2 + v);
    EXPECT_THROW(source->readSlab(4, 2, slab), std::out_of_range);
}

TEST(Readers, OnlyFormatsWithSeparateSlicesStream) {
    GVR_REQUIRE_SHARED_DATA();
    EXPECT_TRUE(openSliceSource(test::sharedData("ct-chest-ricord-512"), {}));
    EXPECT_TRUE(openSliceSource(test::sharedData("rgb-brainmaps54-cryosection"), {}));
    EXPECT_FALSE(openSliceSource(test::sharedData("mri-colin27-aal/ch2.nii.gz"), {}));
}

TEST(RawReader, DefaultSpacingWarns) {
    test::TempDir dir;
    test::writeBytes(dir.path("v.raw"), std::string(8, '\1'));
    ReadOptions options;
    options.raw = RawLayout{{2, 2, 2}, SampleType::UInt8, 1, false, 0};
    const DenseVolume volume = readVolume(dir.path("v.raw"), options);
    ASSERT_EQ(volume.warnings.size(), 1u);
    EXPECT_NE(volume.warnings[0].find("spacing is unknown"), std::string::npos);
}

std::string metaHeader(const std::string& extra, const std::string& dataFile) {
    return "ObjectType = Image\nNDims = 3\nDimSize = 2 2 1\nElementType = MET_SHORT\n"
           "ElementSpacing = 0.5 0.25 3\nOffset = 10 20 30\n"
           "TransformMatrix = 0 1 0 -1 0 0 0 0 1\n" +
           extra + "ElementDataFile = " + dataFile + "\n";
}

std::string shortSamples(const std::vector<std::int16_t>& values, bool bigEndian) {
    std::string bytes;
    for (auto v : values) appendWord(bytes, v, bigEndian);
    return bytes;
}

TEST(MetaImageReader, LocalDataWithOrientationBecomesRas) {
    test::TempDir dir;
    const std::vector<std::int16_t> values{-5, 6, 700, -800};
    test::writeBytes(dir.path("v.mha"),
                     metaHeader("BinaryDataByteOrderMSB = True\n", "LOCAL") + shortSamples(values, true));
    const DenseVolume volume = readMetaImage(dir.path("v.mha"), {});
    for (std::size_t v = 0; v < values.size(); ++v) EXPECT_EQ(volume.data<std::int16_t>()[v], values[v]);
    // LPS: axis i runs along +y (0.5 mm), axis j along -x (0.25 mm); RAS flips x and y.
    expectNear(worldOf(volume, {0, 0, 0}), {-10, -20, 30});
    expectNear(worldOf(volume, {1, 0, 0}), {-10, -20.5, 30});
    expectNear(worldOf(volume, {0, 1, 0}), {-9.75, -20, 30});
}

TEST(MetaImageReader, DetachedAndCompressedData) {
    test::TempDir dir;
    const std::vector<std::int16_t> values{1, 2, 3, 4};
    const std::string plain = shortSamples(values, false);
    uLongf packedSize = compressBound(uLong(plain.size()));
    std::string packed(packedSize, '\0');
    ASSERT_EQ(compress(reinterpret_cast<Bytef*>(packed.data()), &packedSize,
                       reinterpret_cast<const Bytef*>(plain.data()), uLong(plain.size())),
              Z_OK);
    packed.resize(packedSize);
    test::writeBytes(dir.path("v.zraw"), packed);
    test::writeBytes(dir.path("v.mhd"), metaHeader("CompressedData = True\n", "v.zraw"));
    const DenseVolume volume = readMetaImage(dir.path("v.mhd"), {});
    for (std::size_t v = 0; v < values.size(); ++v) EXPECT_EQ(volume.data<std::int16_t>()[v], values[v]);

    test::writeBytes(dir.path("v.zraw"), packed.substr(0, packed.size() / 2));
    EXPECT_THROW(readMetaImage(dir.path("v.mhd"), {}), InputError);
}

TEST(MetaImageReader, DataFilesOutsideTheHeadersFolderNeedPermission) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.path("headers/sub"));
    const std::string samples = shortSamples({1, 2, 3, 4}, false);
    test::writeBytes(dir.path("outside.raw"), samples);
    test::writeBytes(dir.path("headers/sub/inside.raw"), samples);
    for (const std::string& named :
         {std::string("../outside.raw"), dir.path("outside.raw"), std::string("sub/../../outside.raw")}) {
        test::writeBytes(dir.path("headers/v.mhd"), metaHeader("", named));
        try {
            readMetaImage(dir.path("headers/v.mhd"), {});
            ADD_FAILURE() << named << " was read";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find("outside the header's folder"), std::string::npos) << error.what();
        }
        ReadOptions anywhere;
        anywhere.dataFilesAnywhere = true;
        EXPECT_EQ(readMetaImage(dir.path("headers/v.mhd"), anywhere).data<std::int16_t>()[3], 4) << named;
    }
    test::writeBytes(dir.path("headers/v.mhd"), metaHeader("", "sub/inside.raw"));
    EXPECT_EQ(readMetaImage(dir.path("headers/v.mhd"), {}).data<std::int16_t>()[3], 4);
}

// Found by fuzz_metaimage: an ElementDataFile that is empty or names a folder, or
// a name too long for the system, made std::filesystem throw its own exception.
TEST(MetaImageReader, ADataFileThatCannotBeAFileIsRefused) {
    test::TempDir dir;
    std::filesystem::create_directories(dir.path("headers/sub"));
    const std::pair<std::string, std::string> cases[] = {{"", "is not a regular file"},
                                                         {"sub", "is not a regular file"},
                                                         {std::string(5000, 'a'), "does not exist: File name too long"},
                                                         {"v.mhd", "names the header itself"}};
    for (const auto& [named, problem] : cases) {
        test::writeBytes(dir.path("headers/v.mhd"), metaHeader("", named));
        try {
            readMetaImage(dir.path("headers/v.mhd"), {});
            ADD_FAILURE() << "'" << named << "' was read";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find(problem), std::string::npos) << error.what();
        }
    }
}

// Found by fuzz_metaimage: NDims = 1e52 was cast to int, which is undefined.
TEST(MetaImageReader, CountsThatAreNotCountsAreRefused) {
    test::TempDir dir;
    test::writeBytes(dir.path("v.raw"), shortSamples({1, 2, 3, 4}, false));
    const std::tuple<std::string, std::string, std::string> cases[] = {
        {"NDims = 3", "NDims = 1e52", "NDims is 1e52, not a count"},
        {"NDims = 3", "NDims = -2", "NDims is -2, not a count"},
        {"ElementType", "ElementNumberOfChannels = 2.5\nElementType", "ElementNumberOfChannels is 2.5, not a count"},
        {"ElementType", "ElementNumberOfChannels = nan\nElementType", "ElementNumberOfChannels needs 1 numbers"}};
    for (const auto& [from, to, problem] : cases) {
        std::string header = metaHeader("", "v.raw");
        header.replace(header.find(from), from.size(), to);
        test::writeBytes(dir.path("v.mhd"), header);
        try {
            readMetaImage(dir.path("v.mhd"), {});
            ADD_FAILURE() << to << " was read";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find(problem), std::string::npos) << error.what();
        }
    }
}

/// An MGH file of 2x2x2 uint8 in FreeSurfer's LIA orientation, centred at c_ras.
std::string mghBytes() {
    std::string bytes;
    for (std::int32_t v : {1, 2, 2, 2, 1, 0, 0}) appendWord(bytes, v, true);  // version..dof
    appendWord(bytes, std::int16_t(1), true);                                 // goodRAS
    for (float v : {1.f, 1.f, 2.f}) appendWord(bytes, v, true);               // spacing
    for (float v : {-1.f, 0.f, 0.f, 0.f, 0.f, -1.f, 0.f, 1.f, 0.f}) appendWord(bytes, v, true);
    for (float v : {5.f, 6.f, 7.f}) appendWord(bytes, v, true);  // c_ras
    bytes.resize(284, '\0');
    for (int v = 0; v < 8; ++v) bytes.push_back(char(v * 10));
    return bytes;
}

TEST(MghReader, PlainAndGzippedGiveFreeSurferGeometry) {
    test::TempDir dir;
    test::writeBytes(dir.path("v.mgh"), mghBytes());
    gzFile gz = gzopen(dir.path("v.mgz").c_str(), "wb");
    const std::string bytes = mghBytes();
    gzwrite(gz, bytes.data(), unsigned(bytes.size()));
    gzclose(gz);
    for (const char* name : {"v.mgh", "v.mgz"}) {
        const DenseVolume volume = readMgh(dir.path(name), {});
        EXPECT_EQ(volume.data<std::uint8_t>()[7], 70);
        // Centre voxel (1,1,1) lands on c_ras; i runs to -x, j to -z, k to +y (2 mm).
        expectNear(worldOf(volume, {1, 1, 1}), {5, 6, 7});
        expectNear(worldOf(volume, {2, 1, 1}), {4, 6, 7});
        expectNear(worldOf(volume, {1, 2, 1}), {5, 6, 6});
        expectNear(worldOf(volume, {1, 1, 2}), {5, 8, 7});
    }
}

TEST(MghReader, AHeaderOfNoFrameIsRefused) {
    // nframes = 0 was read as one frame.
    test::TempDir dir;
    std::string bytes = mghBytes();
    bytes.replace(16, 4, std::string(4, '\0'));  // nframes, after version and the three dims
    test::writeBytes(dir.path("v.mgh"), bytes);
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { readMgh(dir.path("v.mgh"), {}); }),
              dir.path("v.mgh") + ": corrupt MGH header: nframes is 0; a volume has at least one");
}

/// Writes a NIfTI-1 file through nifticlib itself, so the reader meets real output.
void writeNifti(const std::string& path, const std::vector<std::int64_t>& dims, int datatype, const void* data,
                double slope, double inter, bool shear) {
    std::int64_t nimDims[8] = {std::int64_t(dims.size())};
    for (std::size_t d = 0; d < dims.size(); ++d) nimDims[d + 1] = dims[d];
    nifti_image* image = nifti_make_new_nim(nimDims, datatype, 1);
    std::memcpy(image->data, data, image->nvox * image->nbyper);
    image->scl_slope = slope;
    image->scl_inter = inter;
    image->sform_code = 1;
    image->sto_xyz = nifti_dmat44{};
    image->sto_xyz.m[0][0] = 0.5;
    image->sto_xyz.m[1][1] = 0.5;
    image->sto_xyz.m[2][2] = 2.5;
    image->sto_xyz.m[1][2] = shear ? 0.15 : 0.0;
    image->sto_xyz.m[0][3] = -100;
    image->sto_xyz.m[3][3] = 1;
    nifti_set_filenames(image, path.c_str(), 0, 0);
    nifti_image_write(image);
    nifti_image_free(image);
}

TEST(NiftiReader, AppliesSlopeInterceptAndShearedSform) {
    test::TempDir dir;
    const std::vector<std::uint8_t> stored{0, 1, 100, 255};
    writeNifti(dir.path("shear.nii.gz"), {2, 2, 1}, NIFTI_TYPE_UINT8, stored.data(), 7.1, -1024, true);
    const DenseVolume volume = readNifti(dir.path("shear.nii.gz"), {});
    EXPECT_EQ(volume.type, SampleType::UInt8);
    EXPECT_NEAR(volume.slope, 7.1, 1e-6);  // NIfTI-1 stores it as float32
    EXPECT_DOUBLE_EQ(volume.intercept, -1024);
    EXPECT_EQ(volume.data<std::uint8_t>()[2], 100);
    expectNear(worldOf(volume, {1, 1, 1}), {-99.5, 0.65, 2.5});
    ASSERT_TRUE(volume.niftiCodes);  // kept for a NIfTI export
    EXPECT_EQ(volume.niftiCodes->sform, 1);
}

/// A one-file NIfTI-2 of 2 x 2 x 1 uint8 voxels, laid out field by field as the
/// standard gives it (nifticlib's own writer left its header out here).
std::string niftiTwoBytes(const std::vector<std::uint8_t>& voxels) {
    std::string bytes(544, '\0');  // the 540-byte header and an empty extension flag
    const auto put = [&](std::size_t offset, auto value) { std::memcpy(&bytes[offset], &value, sizeof value); };
    put(0, std::int32_t(540));
    std::memcpy(&bytes[4], "n+2\0\r\n\032\n", 8);
    put(12, std::int16_t(NIFTI_TYPE_UINT8));
    put(14, std::int16_t(8));
    const std::int64_t dim[8] = {3, 2, 2, 1, 1, 1, 1, 1};
    for (int d = 0; d < 8; ++d) put(16 + 8 * d, dim[d]);
    for (int d = 0; d < 8; ++d) put(104 + 8 * d, 1.0);
    put(168, std::int64_t(544));  // vox_offset
    put(176, 2.0);                // scl_slope
    put(184, -10.0);              // scl_inter
    put(348, std::int32_t(1));    // sform_code
    const double rows[3][4] = {{0.5, 0, 0, -100}, {0, 0.5, 0, 0}, {0, 0, 2.5, 0}};
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) put(400 + 32 * r + 8 * c, rows[r][c]);
    }
    return bytes + std::string(voxels.begin(), voxels.end());
}

TEST(NiftiReader, ReadsNiftiTwo) {
    // Its vox_offset is an int64, which was read as a double: "vox_offset 2.68772e-321
    // is not a usable data offset".
    test::TempDir dir;
    test::writeBytes(dir.path("two.nii"), niftiTwoBytes({0, 1, 100, 255}));
    const DenseVolume volume = readNifti(dir.path("two.nii"), {});
    EXPECT_EQ(volume.type, SampleType::UInt8);
    EXPECT_DOUBLE_EQ(volume.slope, 2.0);
    EXPECT_DOUBLE_EQ(volume.intercept, -10);
    EXPECT_EQ(volume.data<std::uint8_t>()[3], 255);
    expectNear(worldOf(volume, {1, 1, 0}), {-99.5, 0.5, 0.0});
}

TEST(NiftiReader, ADimensionCountBelowOneIsRefused) {
    // dim[0] = 0 was read as a volume of the sizes after it.
    test::TempDir dir;
    const std::uint8_t values[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    writeNifti(dir.path("v.nii"), {2, 2, 2}, DT_UINT8, values, 1.0, 0.0, false);
    std::string bytes = test::readBytes(dir.path("v.nii"));
    for (const std::int16_t dimensions : {0, -3}) {
        std::memcpy(&bytes[40], &dimensions, sizeof dimensions);  // the host's order, as nifticlib wrote it
        test::writeBytes(dir.path("bad.nii"), bytes);
        EXPECT_EQ(test::errorMessageOf<InputError>([&] { readNifti(dir.path("bad.nii"), {}); }),
                  dir.path("bad.nii") + ": corrupt NIfTI header: dim[0] is " + std::to_string(dimensions) +
                      "; it counts the dimensions, 1 to 7");
    }
}

TEST(NiftiReader, SelectsAVolumeOfA4DSeries) {
    test::TempDir dir;
    std::vector<float> values(2 * 1 * 1 * 3);
    for (std::size_t v = 0; v < values.size(); ++v) values[v] = float(v) - 2.5f;
    writeNifti(dir.path("series.nii"), {2, 1, 1, 3}, NIFTI_TYPE_FLOAT32, values.data(), 0, 0, false);
    ReadOptions options;
    options.volumeIndex = 2;
    const DenseVolume volume = readNifti(dir.path("series.nii"), options);
    EXPECT_EQ(volume.data<float>()[0], 1.5f);
    EXPECT_EQ(volume.data<float>()[1], 2.5f);
    options.volumeIndex = 3;
    EXPECT_THROW(readNifti(dir.path("series.nii"), options), InputError);
}

TEST(NiftiReader, ReadsRgb24AsThreeChannels) {
    test::TempDir dir;
    const std::vector<std::uint8_t> rgb{255, 0, 0, 0, 255, 0};
    writeNifti(dir.path("rgb.nii.gz"), {2, 1, 1}, NIFTI_TYPE_RGB24, rgb.data(), 0, 0, false);
    const DenseVolume volume = readNifti(dir.path("rgb.nii.gz"), {});
    EXPECT_EQ(volume.channels, 3);
    EXPECT_EQ(volume.data<std::uint8_t>()[4], 255);
}

void writeImage(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type, const void* pixels) {
    auto output = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(output);
    OIIO::ImageSpec spec(width, height, channels, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // the bytes as given, alpha or not
    ASSERT_TRUE(output->open(path, spec));
    ASSERT_TRUE(output->write_image(type, pixels));
    output->close();
}

TEST(ImageStackReader, SortsNumericallyAndKeeps16Bits) {
    test::TempDir dir;
    std::filesystem::create_directory(dir.path("stack"));
    for (int slice : {1, 2, 10}) {
        const std::vector<std::uint16_t> pixels(6, std::uint16_t(slice * 1000));
        writeImage(dir.path("stack/" + std::to_string(slice) + ".png"), 3, 2, 1, OIIO::TypeDesc::UINT16, pixels.data());
    }
    test::writeBytes(dir.path("stack/README.txt"), "not an image");
    const DenseVolume volume = readVolume(dir.path("stack"), {});
    EXPECT_EQ(volume.type, SampleType::UInt16);
    ASSERT_EQ(volume.dims[2], 3);
    EXPECT_EQ(volume.data<std::uint16_t>()[0], 1000);
    EXPECT_EQ(volume.data<std::uint16_t>()[6], 2000);
    EXPECT_EQ(volume.data<std::uint16_t>()[12], 10000);

    const DenseVolume globbed = readVolume(dir.path("stack/*.png"), {});
    EXPECT_EQ(globbed.data<std::uint16_t>()[12], 10000);
}

TEST(ImageStackReader, ReadsMultiPageTiffAsSlices) {
    test::TempDir dir;
    const std::string path = dir.path("pages.tif");
    auto output = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(output && output->supports("multiimage"));
    const OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8),
                                      OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8)};
    ASSERT_TRUE(output->open(path, 2, specs));
    for (int page = 0; page < 2; ++page) {
        if (page > 0) {
            ASSERT_TRUE(output->open(path, specs[page], OIIO::ImageOutput::AppendSubimage));
        }
        const std::vector<std::uint8_t> pixels(12, std::uint8_t(50 + page * 100));
        ASSERT_TRUE(output->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    }
    output->close();
    const DenseVolume volume = readVolume(path, {});
    EXPECT_EQ(volume.channels, 3);
    EXPECT_EQ(volume.dims[2], 2);
    EXPECT_EQ(volume.data<std::uint8_t>()[12], 150);
}

TEST(ImageStackReader, IntegerTiffsKeepTheirValues) {
    // Asked for float, OpenImageIO once scaled int16 HU -1024..2036 to -0.031..0.062.
    test::TempDir dir;
    const std::vector<std::int16_t> hu = {-1024, -500, 0, 40, 1000, 2036};
    writeImage(dir.path("ct.tif"), 3, 2, 1, OIIO::TypeDesc::INT16, hu.data());
    const DenseVolume volume = readVolume(dir.path("ct.tif"), {});
    ASSERT_EQ(volume.type, SampleType::Int16);
    for (std::size_t n = 0; n < hu.size(); ++n) EXPECT_EQ(volume.data<std::int16_t>()[n], hu[n]);
    const std::vector<std::int32_t> wide = {-70000, 5, 70000, 0, 1, 2};
    writeImage(dir.path("wide.tif"), 3, 2, 1, OIIO::TypeDesc::INT32, wide.data());
    const DenseVolume widened = readVolume(dir.path("wide.tif"), {});
    ASSERT_EQ(widened.type, SampleType::Int32);
    EXPECT_EQ(widened.data<std::int32_t>()[0], -70000);
}

TEST(ImageStackReader, AlphaNeitherScalesNorZeroesTheValues) {
    // Premultiplied by OpenImageIO, alpha 0 once zeroed the volume.
    test::TempDir dir;
    const std::vector<std::uint8_t> greyAlpha = {200, 0, 100, 128, 50, 255, 10, 0};  // (grey, alpha) x 4
    writeImage(dir.path("ga.png"), 2, 2, 2, OIIO::TypeDesc::UINT8, greyAlpha.data());
    const DenseVolume grey = readVolume(dir.path("ga.png"), {});
    ASSERT_EQ(grey.channels, 1);
    EXPECT_EQ(std::vector<std::uint8_t>(grey.data<std::uint8_t>(), grey.data<std::uint8_t>() + 4),
              (std::vector<std::uint8_t>{200, 100, 50, 10}));
    EXPECT_NE(
        std::find_if(grey.warnings.begin(), grey.warnings.end(),
                     [](const std::string& w) { return w.find("alpha channel is ignored") != std::string::npos; }),
        grey.warnings.end());
    const std::vector<std::uint8_t> rgba = {200, 100, 50, 0, 1, 2, 3, 128, 9, 8, 7, 255, 90, 80, 70, 0};
    writeImage(dir.path("rgba.png"), 2, 2, 4, OIIO::TypeDesc::UINT8, rgba.data());
    const DenseVolume colour = readVolume(dir.path("rgba.png"), {});
    ASSERT_EQ(colour.channels, 3);
    EXPECT_EQ(std::vector<std::uint8_t>(colour.data<std::uint8_t>(), colour.data<std::uint8_t>() + 12),
              (std::vector<std::uint8_t>{200, 100, 50, 1, 2, 3, 9, 8, 7, 90, 80, 70}));
}

}  // namespace
}  // namespace gvr
