// Sample blocks after a header: plain, gzip'd as a whole, or a zlib stream. The
// samples are converted to host order; short, cut and damaged data are refused.

#include "io/formats/SampleFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

namespace gvr {
namespace {

const std::string kHeader = "HEAD!";  // 5 bytes: samples start at an odd offset

/// 64 x 64 int16 samples with both extremes, scrambled so that deflate cannot
/// shrink them much: a cut stream then really loses samples.
std::vector<std::int16_t> scrambledValues() {
    std::vector<std::int16_t> values(64 * 64);
    for (std::uint32_t n = 0; n < values.size(); ++n) values[n] = std::int16_t(std::uint16_t((n * 2654435761u) >> 13));
    values[0] = -32768;
    values[1] = 32767;
    values[2] = -1;
    return values;
}

std::string bigEndianBytes(const std::vector<std::int16_t>& values) {
    std::string bytes;
    for (const std::int16_t v : values) {
        bytes.push_back(char(std::uint16_t(v) >> 8));
        bytes.push_back(char(std::uint16_t(v) & 0xff));
    }
    return bytes;
}

DenseVolume int16Volume() {
    DenseVolume volume;
    volume.dims = {64, 64, 1};
    volume.type = SampleType::Int16;
    return volume;
}

void expectValues(const DenseVolume& volume, const std::vector<std::int16_t>& values) {
    ASSERT_EQ(volume.samples.size(), values.size() * 2);
    for (std::size_t n = 0; n < values.size(); ++n) ASSERT_EQ(volume.data<std::int16_t>()[n], values[n]) << n;
}

void writeGzip(const std::string& path, const std::string& bytes) {
    gzFile out = gzopen(path.c_str(), "wb");
    ASSERT_NE(out, nullptr);
    ASSERT_EQ(gzwrite(out, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
    ASSERT_EQ(gzclose(out), Z_OK);
}

std::string zlibCompressed(const std::string& bytes) {
    uLongf size = compressBound(uLong(bytes.size()));
    std::string out(size, '\0');
    EXPECT_EQ(compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                        uLong(bytes.size()), 9),
              Z_OK);
    out.resize(size);
    return out;
}

TEST(SampleFile, PlainBigEndianSamplesArriveInHostOrder) {
    test::TempDir dir;
    const std::vector<std::int16_t> values = scrambledValues();
    const std::string path = dir.path("v.img");
    test::writeBytes(path, kHeader + bigEndianBytes(values));
    DenseVolume volume = int16Volume();
    readPlainSamples(path, kHeader.size(), true, volume);
    expectValues(volume, values);
    EXPECT_TRUE(volume.warnings.empty());
}

TEST(SampleFile, PlainLittleEndianSamplesAreTakenAsTheyAre) {
    test::TempDir dir;
    const std::string path = dir.path("v.img");
    // -32768, -1, 1, 32767 in little-endian order.
    test::writeBytes(path, std::string("\x00\x80\xff\xff\x01\x00\xff\x7f", 8));
    DenseVolume volume;
    volume.dims = {2, 2, 1};
    volume.type = SampleType::Int16;
    readPlainSamples(path, 0, false, volume);
    expectValues(volume, {-32768, -1, 1, 32767});
}

TEST(SampleFile, PlainBytesBeyondTheSamplesAreAWarningAndTooFewAnError) {
    test::TempDir dir;
    const std::string samples = bigEndianBytes(scrambledValues());
    const std::string path = dir.path("v.img");
    test::writeBytes(path, kHeader + samples + "xyz");
    DenseVolume volume = int16Volume();
    readPlainSamples(path, kHeader.size(), true, volume);
    ASSERT_EQ(volume.warnings.size(), 1u);
    EXPECT_EQ(volume.warnings[0], path + ": 3 bytes after the voxel data are ignored");

    test::writeBytes(path, kHeader + samples.substr(0, samples.size() - 1));
    DenseVolume shortVolume = int16Volume();
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { readPlainSamples(path, kHeader.size(), true, shortVolume); }),
              path + ": truncated: voxel data needs 8197 bytes, the file has 8196");
}

TEST(SampleFile, GzipRoundTripAndAnUncompressedFileReadTheSame) {
    test::TempDir dir;
    const std::vector<std::int16_t> values = scrambledValues();
    writeGzip(dir.path("v.nii.gz"), kHeader + bigEndianBytes(values));
    DenseVolume volume = int16Volume();
    readGzipSamples(dir.path("v.nii.gz"), kHeader.size(), true, volume);
    expectValues(volume, values);
    // zlib reads a file without gzip framing as it is, so a plain .nii takes the same path.
    test::writeBytes(dir.path("v.nii"), kHeader + bigEndianBytes(values));
    DenseVolume plain = int16Volume();
    readGzipSamples(dir.path("v.nii"), kHeader.size(), true, plain);
    expectValues(plain, values);
}

TEST(SampleFile, GzipWithABadCrcOrCutShortIsRefused) {
    test::TempDir dir;
    const std::string path = dir.path("v.nii.gz");
    writeGzip(path, kHeader + bigEndianBytes(scrambledValues()));
    const std::string gz = test::readBytes(path);

    std::string badCrc = gz;
    badCrc[badCrc.size() - 8] ^= 1;  // the trailer: CRC-32, then the length
    test::writeBytes(path, badCrc);
    DenseVolume volume = int16Volume();
    const std::string corrupt =
        test::errorMessageOf<InputError>([&] { readGzipSamples(path, kHeader.size(), true, volume); });
    EXPECT_EQ(corrupt.rfind(path + ": corrupt compressed data (zlib: ", 0), 0u) << corrupt;

    test::writeBytes(path, gz.substr(0, gz.size() / 2));
    DenseVolume cutVolume = int16Volume();
    const std::string cut =
        test::errorMessageOf<InputError>([&] { readGzipSamples(path, kHeader.size(), true, cutVolume); });
    EXPECT_EQ(cut.rfind(path + ": truncated", 0), 0u) << cut;

    // Every sample is there, but the CRC that vouches for them is cut off.
    test::writeBytes(path, gz.substr(0, gz.size() - 4));
    DenseVolume noTrailer = int16Volume();
    const std::string trailer =
        test::errorMessageOf<InputError>([&] { readGzipSamples(path, kHeader.size(), true, noTrailer); });
    EXPECT_EQ(trailer, path + ": truncated: the compressed stream ends before its checksum") << trailer;
}

TEST(SampleFile, DeflatedRoundTripAfterAHeader) {
    test::TempDir dir;
    const std::vector<std::int16_t> values = scrambledValues();
    const std::string path = dir.path("v.mha");
    test::writeBytes(path, kHeader + zlibCompressed(bigEndianBytes(values)));
    DenseVolume volume = int16Volume();
    readDeflatedSamples(path, kHeader.size(), true, volume);
    expectValues(volume, values);
}

TEST(SampleFile, DeflatedStreamsThatAreDamagedOrCutAreRefused) {
    test::TempDir dir;
    const std::string path = dir.path("v.mha");
    const std::string stream = zlibCompressed(bigEndianBytes(scrambledValues()));
    const auto errorFor = [&](const std::string& data) {
        test::writeBytes(path, kHeader + data);
        DenseVolume volume = int16Volume();
        return test::errorMessageOf<InputError>([&] { readDeflatedSamples(path, kHeader.size(), true, volume); });
    };
    std::string badAdler = stream;
    badAdler.back() ^= 1;
    EXPECT_EQ(errorFor(badAdler),
              path + ": corrupt compressed voxel data (zlib error " + std::to_string(Z_DATA_ERROR) + ")");
    // Every sample is there, but the Adler-32 that vouches for them is not.
    EXPECT_EQ(errorFor(stream.substr(0, stream.size() - 4)),
              path + ": truncated: the compressed stream ends before its checksum");
    const std::string half = errorFor(stream.substr(0, stream.size() / 2));
    EXPECT_EQ(half.rfind(path + ": truncated: compressed voxel data inflates to ", 0), 0u) << half;
    EXPECT_NE(half.find("bytes, expected 8192"), std::string::npos) << half;
}

}  // namespace
}  // namespace gvr
