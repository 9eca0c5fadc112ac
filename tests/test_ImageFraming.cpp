// Image framing: whole PNG, JPEG and BMP files pass; cut, damaged or compressed
// ones are refused by name before OpenImageIO sees them. The files are built here
// byte by byte, since only their framing is checked, not their pixels.

#include "io/guard/ImageFraming.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <string>

namespace gvr {
namespace {

std::string bigEndian32(std::uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

std::string pngChunk(const std::string& type, const std::string& data) {
    const std::string body = type + data;
    const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()));
    return bigEndian32(std::uint32_t(data.size())) + body + bigEndian32(std::uint32_t(crc));
}

const std::string kPngSignature("\x89PNG\r\n\x1a\n", 8);

/// Signature (8 bytes), IHDR (25), IDAT (16, its data at byte 41), IEND (12).
std::string wholePng() {
    return kPngSignature + pngChunk("IHDR", std::string(13, '\1')) + pngChunk("IDAT", "data") + pngChunk("IEND", "");
}

/// A BITMAPINFOHEADER (54 bytes) followed by @a pixelBytes bytes.
std::string bmp(std::int32_t width, std::int32_t height, std::uint16_t bits, std::uint32_t compression,
                std::size_t pixelBytes) {
    std::string header = "BM" + test::littleEndian32(std::uint32_t(54 + pixelBytes)) + test::littleEndian32(0) +
                         test::littleEndian32(54) + test::littleEndian32(40) +
                         test::littleEndian32(std::uint32_t(width)) + test::littleEndian32(std::uint32_t(height)) +
                         test::littleEndian16(1) + test::littleEndian16(bits) + test::littleEndian32(compression);
    header.resize(54, '\0');
    return header + std::string(pixelBytes, '\x7f');
}

/// The message checkImageFraming throws for @a bytes, written to @a path; "" when it passes.
std::string framingError(const std::string& path, const std::string& bytes) {
    test::writeBytes(path, bytes);
    return test::errorMessageOf<InputError>([&] { checkImageFraming(path); });
}

TEST(ImageFraming, WholeFilesAndOtherFormatsPass) {
    test::TempDir dir;
    EXPECT_EQ(framingError(dir.path("a.png"), wholePng()), "");
    EXPECT_EQ(framingError(dir.path("a.jpg"), "\xff\xd8\xff\xe0" + std::string(200, 'x') + "\xff\xd9"), "");
    // A little padding after the end-of-image marker is common and harmless.
    EXPECT_EQ(framingError(dir.path("b.jpg"), "\xff\xd8\xff\xe0" + std::string(200, 'x') + "\xff\xd9\n\n"), "");
    // 2 x 2 pixels of 24 bits: rows padded to 8 bytes.
    EXPECT_EQ(framingError(dir.path("a.bmp"), bmp(2, 2, 24, 0, 16)), "");
    EXPECT_EQ(framingError(dir.path("top-down.bmp"), bmp(2, -2, 24, 0, 16)), "");
    EXPECT_EQ(framingError(dir.path("a.gif"), "GIF89a: not a format that is checked"), "");
}

TEST(ImageFraming, EveryCutOfAPngIsRefusedAsTruncated) {
    test::TempDir dir;
    const std::string png = wholePng(), path = dir.path("cut.png");
    for (std::size_t keep = kPngSignature.size(); keep < png.size(); ++keep) {
        const std::string message = framingError(path, png.substr(0, keep));
        EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << keep << ": " << message;
        EXPECT_NE(message.find("truncated"), std::string::npos) << keep << ": " << message;
    }
    EXPECT_EQ(framingError(path, kPngSignature + pngChunk("IHDR", std::string(13, '\1'))),
              path + ": truncated PNG: it ends before its IEND chunk");
}

TEST(ImageFraming, ADamagedPngChunkFailsItsCrc) {
    test::TempDir dir;
    std::string png = wholePng();
    png[41] ^= 0x20;
    EXPECT_EQ(framingError(dir.path("bad.png"), png),
              dir.path("bad.png") + ": corrupt PNG: chunk 'IDAT' fails its CRC check");
}

TEST(ImageFraming, APngChunkClaimingFourGibibytesIsRefused) {
    test::TempDir dir;
    const std::string png = kPngSignature + bigEndian32(0xffffffffu) + "IDAT" + std::string(8, '\0');
    EXPECT_EQ(framingError(dir.path("huge.png"), png),
              dir.path("huge.png") + ": truncated or corrupt PNG: chunk 'IDAT' runs past the end of the file");
}

TEST(ImageFraming, AJpegWithoutItsEndMarkerIsRefused) {
    test::TempDir dir;
    EXPECT_EQ(framingError(dir.path("cut.jpg"), "\xff\xd8\xff\xe0" + std::string(200, 'x')),
              dir.path("cut.jpg") + ": truncated JPEG: no end-of-image marker");
}

TEST(ImageFraming, BmpsThatAreCutCompressedOrEmptyAreRefused) {
    test::TempDir dir;
    const std::string path = dir.path("x.bmp");
    EXPECT_EQ(framingError(path, bmp(2, 2, 24, 0, 15)),
              path + ": truncated BMP: its pixels need 70 bytes, the file has 69");
    // Run-length coding on 24 bits made OpenImageIO read before its buffer.
    EXPECT_EQ(framingError(path, bmp(2, 2, 24, 1, 16)),
              path + ": unsupported BMP: 24 bits a pixel with compression 1; gvr reads uncompressed BMP");
    EXPECT_EQ(framingError(path, bmp(2, 2, 7, 0, 16)),
              path + ": unsupported BMP: 7 bits a pixel with compression 0; gvr reads uncompressed BMP");
    EXPECT_EQ(framingError(path, bmp(0, 2, 24, 0, 16)), path + ": corrupt BMP: its size is 0x2");
    EXPECT_EQ(framingError(path, bmp(-2, 2, 24, 0, 16)), path + ": corrupt BMP: its size is -2x2");
    // The largest header sizes: about 2^64 bytes of pixels, computed without wrapping to a small size.
    const std::string huge = framingError(path, bmp(0x7fffffff, 0x7fffffff, 32, 0, 16));
    EXPECT_EQ(huge.rfind(path + ": truncated BMP: its pixels need ", 0), 0u) << huge;
    EXPECT_EQ(framingError(path, "BM" + std::string(20, '\0')), path + ": truncated BMP: its header is cut");
}

TEST(ImageFraming, AMissingFileIsNamed) {
    test::TempDir dir;
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { checkImageFraming(dir.path("none.png")); }),
              dir.path("none.png") + ": cannot open file");
}

}  // namespace
}  // namespace gvr
