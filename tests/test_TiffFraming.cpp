// TIFF framing: whole classic and BigTIFF files pass in both byte orders; a file cut
// at any byte, or whose page chain loops, is refused by name before OpenImageIO
// sees it. The files are built here word by word, since only their framing is read.

#include "io/guard/TiffFraming.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace gvr {
namespace {

struct TiffShape {
    bool bigEndian = false;
    bool bigTiff = false;
    int pages = 3;
    int stripsPerPage = 1;  // two strips put a classic file's strip table outside its directory
};

class TiffBuilder {
public:
    explicit TiffBuilder(TiffShape shape) : mShape(shape) {}

    /// Pages of 2 x 2 grey 8-bit pixels, each a directory followed by its strips.
    std::string build() {
        mBytes = mShape.bigEndian ? "MM" : "II";
        if (mShape.bigTiff) {
            put(43, 2), put(8, 2), put(0, 2), put(16, 8);
        } else {
            put(42, 2), put(8, 4);
        }
        for (int page = 0; page < mShape.pages; ++page) addPage(page + 1 == mShape.pages);
        return mBytes;
    }

    /// Where the next-directory pointer of the first page lies.
    std::size_t firstNextPointer() const { return mFirstNextPointer; }

private:
    void put(std::uint64_t value, int width) {
        for (int b = 0; b < width; ++b) {
            const int shift = 8 * (mShape.bigEndian ? width - 1 - b : b);
            mBytes.push_back(char((value >> shift) & 0xff));
        }
    }
    int wordBytes() const { return mShape.bigTiff ? 8 : 4; }

    /// A SHORT or LONG entry of one value, left-justified in its value field.
    void entry(std::uint16_t tag, std::uint16_t type, std::uint64_t value) {
        put(tag, 2), put(type, 2), put(1, wordBytes());
        const int width = type == 3 ? 2 : 4;
        put(value, width), put(0, wordBytes() - width);
    }

    void addPage(bool last) {
        const int strips = mShape.stripsPerPage;
        const std::uint64_t entries = 8;
        const std::uint64_t directoryBytes =
            (mShape.bigTiff ? 8 : 2) + entries * (mShape.bigTiff ? 20 : 12) + wordBytes();
        const std::uint64_t tables = strips > 1 ? 2 * 4 * strips : 0;  // two LONG tables, outside when they do not fit
        const bool tablesOutside = strips * 4 > wordBytes();
        const std::uint64_t tableAt = mBytes.size() + directoryBytes;
        const std::uint64_t stripsAt = tableAt + (tablesOutside ? tables : 0);
        const std::uint64_t stripBytes = 4 / strips;
        mShape.bigTiff ? put(entries, 8) : put(entries, 2);
        entry(256, 3, 2), entry(257, 3, 2), entry(258, 3, 8), entry(262, 3, 1);
        stripTable(273, strips, tablesOutside, tableAt, [&](int s) { return stripsAt + s * stripBytes; });
        entry(277, 3, 1), entry(278, 3, std::uint64_t(2 / strips));
        stripTable(279, strips, tablesOutside, tableAt + 4 * strips, [&](int) { return stripBytes; });
        if (mFirstNextPointer == 0) mFirstNextPointer = mBytes.size();
        put(last ? 0 : stripsAt + 4, wordBytes());
        if (tablesOutside) {
            for (int s = 0; s < strips; ++s) put(stripsAt + s * stripBytes, 4);
            for (int s = 0; s < strips; ++s) put(stripBytes, 4);
        }
        mBytes += std::string(4, '\x7f');
    }

    template <typename ValueOf>
    void stripTable(std::uint16_t tag, int strips, bool outside, std::uint64_t tableAt, ValueOf valueOf) {
        if (strips == 1) return entry(tag, 4, valueOf(0));
        put(tag, 2), put(4, 2), put(std::uint64_t(strips), wordBytes());
        if (outside) return put(tableAt, wordBytes());
        for (int s = 0; s < strips; ++s) put(valueOf(s), 4);
        put(0, wordBytes() - 4 * strips);
    }

    TiffShape mShape;
    std::string mBytes;
    std::size_t mFirstNextPointer = 0;
};

std::string tiffFramingError(const std::string& path, const std::string& bytes) {
    test::writeBytes(path, bytes);
    std::ifstream in(path, std::ios::binary);
    return test::errorMessageOf<InputError>([&] { checkTiffFraming(path, in, bytes.size()); });
}

std::vector<TiffShape> everyShape() {
    std::vector<TiffShape> shapes;
    for (const bool bigEndian : {false, true}) {
        for (const bool bigTiff : {false, true}) {
            for (const int strips : {1, 2}) shapes.push_back({bigEndian, bigTiff, 3, strips});
        }
    }
    return shapes;
}

std::string nameOf(const TiffShape& shape) {
    return std::string(shape.bigEndian ? "big-endian " : "little-endian ") + (shape.bigTiff ? "BigTIFF" : "TIFF") +
           " with " + std::to_string(shape.stripsPerPage) + " strips a page";
}

TEST(TiffFraming, RecognisesEverySignature) {
    for (const char* head : {"II*\0", "MM\0*", "II+\0", "MM\0+"}) EXPECT_TRUE(isTiffSignature(std::string(head, 4)));
    EXPECT_FALSE(isTiffSignature(std::string("II\0*", 4)));
    EXPECT_FALSE(isTiffSignature("II"));
}

TEST(TiffFraming, WholeFilesPass) {
    test::TempDir dir;
    for (const TiffShape& shape : everyShape()) {
        EXPECT_EQ(tiffFramingError(dir.path("whole.tif"), TiffBuilder(shape).build()), "") << nameOf(shape);
    }
}

TEST(TiffFraming, AFileCutAtAnyByteIsRefused) {
    test::TempDir dir;
    for (const TiffShape& shape : everyShape()) {
        const std::string whole = TiffBuilder(shape).build();
        for (std::size_t size = 0; size < whole.size(); ++size) {
            const std::string message = tiffFramingError(dir.path("cut.tif"), whole.substr(0, size));
            EXPECT_NE(message.find(dir.path("cut.tif") + ": truncated TIFF: "), std::string::npos)
                << nameOf(shape) << " cut to " << size << " bytes: " << message;
        }
    }
}

TEST(TiffFraming, TheMessageNamesThePageThatIsMissing) {
    test::TempDir dir;
    const std::string whole = TiffBuilder({}).build();
    // After the 8-byte header, each page is a 102-byte directory and 4 bytes of pixels.
    ASSERT_EQ(whole.size(), 8u + 3 * 106);
    EXPECT_EQ(tiffFramingError(dir.path("cut.tif"), whole.substr(0, 8 + 2 * 106 + 20)),
              dir.path("cut.tif") +
                  ": truncated TIFF: page 3's directory at byte 220 runs past the end of the file "
                  "(240 bytes)");
    EXPECT_EQ(tiffFramingError(dir.path("cut.tif"), whole.substr(0, whole.size() - 1)),
              dir.path("cut.tif") + ": truncated TIFF: page 3's pixel data runs to byte 326, the file has 325");
}

TEST(TiffFraming, APageChainThatLoopsIsRefused) {
    test::TempDir dir;
    TiffBuilder builder({});
    std::string bytes = builder.build();
    bytes.replace(builder.firstNextPointer(), 4, test::littleEndian32(8));  // page 1 points back at itself
    EXPECT_EQ(tiffFramingError(dir.path("loop.tif"), bytes),
              dir.path("loop.tif") + ": corrupt TIFF: its page directories form a loop");
}

}  // namespace
}  // namespace gvr
