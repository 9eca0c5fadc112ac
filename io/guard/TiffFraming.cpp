#include "io/guard/TiffFraming.h"

#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <algorithm>
#include <set>
#include <vector>

namespace gvr {

namespace {

/// The tags whose values locate a page's pixels, in pairs: where each piece starts, and its length.
constexpr std::uint16_t kStripOffsets = 273, kStripByteCounts = 279;
constexpr std::uint16_t kTileOffsets = 324, kTileByteCounts = 325;

/// Classic TIFF counts and points with 16- and 32-bit words; BigTIFF with 64-bit ones.
struct TiffWords {
    bool bigEndian = false;
    bool bigTiff = false;
    std::uint64_t countBytes() const { return bigTiff ? 8 : 2; }
    std::uint64_t offsetBytes() const { return bigTiff ? 8 : 4; }
    std::uint64_t entryBytes() const { return bigTiff ? 20 : 12; }
};

class TiffReader {
public:
    TiffReader(const std::string& file, std::istream& in, std::uint64_t size, TiffWords words)
        : mFile(file), mIn(in), mSize(size), mWords(words) {}

    const TiffWords& words() const { return mWords; }

    /// The @a count bytes at @a at; @a what names them in the error when they are not all in the file.
    std::string bytesAt(std::uint64_t at, std::uint64_t count, const std::string& what) const {
        if (at > mSize || count > mSize - at) {
            throw InputError(mFile, "truncated TIFF: " + what + " at byte " + std::to_string(at) +
                                        " runs past the end of the file (" + std::to_string(mSize) + " bytes)");
        }
        std::string bytes(std::size_t(count), '\0');
        mIn.clear();
        mIn.seekg(std::streamoff(at));
        mIn.read(bytes.data(), std::streamsize(count));
        if (std::uint64_t(mIn.gcount()) != count) throw InputError(mFile, "cannot read " + what);
        return bytes;
    }

    /// The unsigned word of @a width bytes (2, 4 or 8) at @a at in @a bytes.
    std::uint64_t word(const std::string& bytes, std::size_t at, std::uint64_t width) const {
        if (width == 2) return loadWord<std::uint16_t>(&bytes[at], mWords.bigEndian);
        if (width == 4) return loadWord<std::uint32_t>(&bytes[at], mWords.bigEndian);
        return loadWord<std::uint64_t>(&bytes[at], mWords.bigEndian);
    }

    void checkExtent(std::uint64_t start, std::uint64_t length, const std::string& page) const {
        if (start > mSize || length > mSize - start) {
            throw InputError(mFile, "truncated TIFF: " + page + "'s pixel data runs to byte " +
                                        std::to_string(start + length) + ", the file has " + std::to_string(mSize));
        }
    }

    const std::string& file() const { return mFile; }
    std::uint64_t size() const { return mSize; }

private:
    const std::string& mFile;
    std::istream& mIn;
    std::uint64_t mSize;
    TiffWords mWords;
};

/// The values of one directory entry of type SHORT, LONG or LONG8: inline when they
/// fit in the entry's value field, elsewhere in the file when not.
std::vector<std::uint64_t> entryValues(const TiffReader& tiff, const std::string& entry, const std::string& page) {
    const TiffWords& words = tiff.words();
    const std::uint64_t type = tiff.word(entry, 2, 2);
    const std::uint64_t width = type == 3 ? 2 : type == 4 ? 4 : type == 16 ? 8 : 0;
    if (width == 0) {
        throw InputError(tiff.file(),
                         "corrupt TIFF: " + page + " gives its pixel locations as field type " + std::to_string(type));
    }
    const std::uint64_t count = tiff.word(entry, 4, words.offsetBytes());
    const std::size_t valueField = 4 + std::size_t(words.offsetBytes());
    std::string values;
    if (count <= words.offsetBytes() / width) {
        values = entry.substr(valueField);
    } else if (count > tiff.size() / width) {
        throw InputError(tiff.file(), "corrupt TIFF: " + page + " lists " + std::to_string(count) +
                                          " pixel pieces, more than the file can hold");
    } else {
        values =
            tiff.bytesAt(tiff.word(entry, valueField, words.offsetBytes()), count * width, page + "'s strip table");
    }
    std::vector<std::uint64_t> result(static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < result.size(); ++i) result[i] = tiff.word(values, i * width, width);
    return result;
}

void checkPieces(const TiffReader& tiff, const std::vector<std::uint64_t>& starts,
                 const std::vector<std::uint64_t>& lengths, const std::string& page) {
    if (starts.size() != lengths.size()) {
        throw InputError(tiff.file(), "corrupt TIFF: " + page + " lists " + std::to_string(starts.size()) +
                                          " pixel pieces but " + std::to_string(lengths.size()) + " lengths");
    }
    for (std::size_t i = 0; i < starts.size(); ++i) tiff.checkExtent(starts[i], lengths[i], page);
}

/// Checks the page whose directory starts at @a at, and returns where the next one starts (0 for none).
std::uint64_t checkPage(const TiffReader& tiff, std::uint64_t at, const std::string& page) {
    const TiffWords& words = tiff.words();
    const std::string what = page + "'s directory";
    const std::uint64_t entries = tiff.word(tiff.bytesAt(at, words.countBytes(), what), 0, words.countBytes());
    // More entries than the file has bytes cannot fit, and would overflow the product.
    const std::uint64_t nextAt = words.countBytes() + std::min(entries, tiff.size()) * words.entryBytes();
    const std::string directory = tiff.bytesAt(at, nextAt + words.offsetBytes(), what);
    constexpr std::uint16_t kTags[4] = {kStripOffsets, kStripByteCounts, kTileOffsets, kTileByteCounts};
    std::vector<std::uint64_t> values[4];
    for (std::uint64_t e = 0; e < entries; ++e) {
        const std::string entry =
            directory.substr(std::size_t(words.countBytes() + e * words.entryBytes()), std::size_t(words.entryBytes()));
        const std::uint64_t tag = tiff.word(entry, 0, 2);
        for (int t = 0; t < 4; ++t) {
            if (tag == kTags[t]) values[t] = entryValues(tiff, entry, page);
        }
    }
    checkPieces(tiff, values[0], values[1], page);
    checkPieces(tiff, values[2], values[3], page);
    return tiff.word(directory, std::size_t(nextAt), words.offsetBytes());
}

}  // namespace

bool isTiffSignature(const std::string& head) {
    return head.compare(0, 4, std::string("II*\0", 4)) == 0 || head.compare(0, 4, std::string("MM\0*", 4)) == 0 ||
           head.compare(0, 4, std::string("II+\0", 4)) == 0 || head.compare(0, 4, std::string("MM\0+", 4)) == 0;
}

void checkTiffFraming(const std::string& file, std::istream& in, std::uint64_t size) {
    TiffWords words;
    const std::string start = TiffReader(file, in, size, words).bytesAt(0, 8, "the header");
    words.bigEndian = start[0] == 'M';
    words.bigTiff = start[2] == '+' || start[3] == '+';
    const TiffReader tiff(file, in, size, words);
    std::uint64_t next = words.bigTiff ? tiff.word(tiff.bytesAt(8, 8, "the header"), 0, 8) : tiff.word(start, 4, 4);
    std::set<std::uint64_t> seen;
    for (std::uint64_t page = 1; next != 0; ++page) {
        if (!seen.insert(next).second) throw InputError(file, "corrupt TIFF: its page directories form a loop");
        next = checkPage(tiff, next, "page " + std::to_string(page));
    }
}

}  // namespace gvr
