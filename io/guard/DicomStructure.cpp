#include "io/guard/DicomStructure.h"

#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <cctype>
#include <cstdint>
#include <fstream>

namespace gvr {

namespace {

constexpr std::uint64_t kUndefinedLength = 0xffffffffu;
constexpr int kMostNesting = 32;
constexpr std::uint64_t kDataAfterPreamble = 132;  // 128-byte preamble, then "DICM"

/// The file's bytes at given offsets, with the file size for bounds.
class ElementReader {
public:
    explicit ElementReader(const std::string& file) : mFile(file), mIn(file, std::ios::binary | std::ios::ate) {
        mSize = mIn ? std::uint64_t(mIn.tellg()) : 0;
    }

    std::uint64_t size() const { return mSize; }
    const std::string& file() const { return mFile; }

    [[noreturn]] void fail() const { throw InputError(mFile, "truncated DICOM file: it ends inside an element"); }

    void read(std::uint64_t at, unsigned char* bytes, std::size_t count) {
        if (at + count > mSize) fail();
        mIn.seekg(std::streamoff(at));
        if (!mIn.read(reinterpret_cast<char*>(bytes), std::streamsize(count))) fail();
    }

    /// The unsigned integer of @a count bytes (2 or 4) at @a at.
    std::uint64_t unsignedAt(std::uint64_t at, std::size_t count, bool bigEndian) {
        unsigned char bytes[4] = {};
        read(at, bytes, count);
        return count == 2 ? loadWord<std::uint16_t>(bytes, bigEndian) : loadWord<std::uint32_t>(bytes, bigEndian);
    }

private:
    std::string mFile;
    std::ifstream mIn;
    std::uint64_t mSize = 0;
};

struct Syntax {
    bool explicitVr = true;
    bool bigEndian = false;
};

struct Element {
    std::uint64_t group = 0, element = 0;
    char vr[2] = {' ', ' '};
    std::uint64_t length = 0;
    std::uint64_t valueAt = 0;

    bool is(std::uint64_t g, std::uint64_t e) const { return group == g && element == e; }
    bool isVr(const char* name) const { return vr[0] == name[0] && vr[1] == name[1]; }
};

/// Explicit-VR elements whose length takes 4 bytes after 2 reserved ones.
bool hasLongLength(const char vr[2]) {
    for (const char* name : {"OB", "OD", "OF", "OL", "OV", "OW", "SQ", "SV", "UC", "UN", "UR", "UT", "UV"}) {
        if (vr[0] == name[0] && vr[1] == name[1]) return true;
    }
    return false;
}

Element readElement(ElementReader& reader, std::uint64_t at, const Syntax& syntax) {
    Element e;
    e.group = reader.unsignedAt(at, 2, syntax.bigEndian);
    e.element = reader.unsignedAt(at + 2, 2, syntax.bigEndian);
    if (e.group == 0xfffe || !syntax.explicitVr) {  // items and delimiters never carry a VR
        e.length = reader.unsignedAt(at + 4, 4, syntax.bigEndian);
        e.valueAt = at + 8;
        return e;
    }
    unsigned char vr[2];
    reader.read(at + 4, vr, 2);
    e.vr[0] = char(vr[0]);
    e.vr[1] = char(vr[1]);
    if (hasLongLength(e.vr)) {
        e.length = reader.unsignedAt(at + 8, 4, syntax.bigEndian);
        e.valueAt = at + 12;
    } else {
        e.length = reader.unsignedAt(at + 6, 2, syntax.bigEndian);
        e.valueAt = at + 8;
    }
    return e;
}

/// Walks elements from @a at up to @a end; nested sequences and items are walked
/// too, and so are the fragments of encapsulated (compressed) pixel data, which
/// must end with their delimiter. Stops at a delimiter (inside an undefined
/// length) or, at the top level, after the pixel data.
/// @param itemsHoldElements  false inside encapsulated pixel data, whose items
///        hold compressed bytes. @return the offset after where it stopped.
std::uint64_t walk(ElementReader& reader, const Syntax& syntax, std::uint64_t at, std::uint64_t end,
                   bool itemsHoldElements, int depth) {
    if (depth > kMostNesting) throw InputError(reader.file(), "corrupt DICOM header: sequences nested too deeply");
    while (at < end) {
        const Element e = readElement(reader, at, syntax);
        if (e.is(0xfffe, 0xe00d) || e.is(0xfffe, 0xe0dd)) return e.valueAt;
        const bool pixelData = depth == 0 && e.is(0x7fe0, 0x0010);
        // Native pixel data may be cut short: the reader reports how many bytes it holds.
        if (pixelData && e.length != kUndefinedLength) return at;
        const bool nestedElements = e.group == 0xfffe ? itemsHoldElements : e.isVr("SQ") || e.isVr("UN");
        if (e.length == kUndefinedLength) {
            const bool encapsulated = e.is(0x7fe0, 0x0010) || e.isVr("OB") || e.isVr("OW");
            // An undefined-length UN holds a sequence in implicit VR little endian.
            const Syntax inside = e.isVr("UN") ? Syntax{false, false} : syntax;
            at = walk(reader, inside, e.valueAt, end, !encapsulated, depth + 1);
            if (pixelData) return at;
            continue;
        }
        if (e.valueAt + e.length > end) reader.fail();
        if (nestedElements && !e.isVr("UN")) walk(reader, syntax, e.valueAt, e.valueAt + e.length, true, depth + 1);
        at = e.valueAt + e.length;
    }
    if (depth > 0 && at >= reader.size()) reader.fail();  // an undefined length never closed
    return at;
}

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\0' || text.back() == ' ')) text.pop_back();
    return text;
}

/// Walks group 0002 (always explicit VR little endian) and returns the data set's
/// transfer syntax UID, or "" when the group does not name one.
std::string walkFileMeta(ElementReader& reader, std::uint64_t& at) {
    const Syntax meta;
    std::string transferSyntax;
    while (at < reader.size()) {
        const Element e = readElement(reader, at, meta);
        if (e.group != 0x0002) break;
        if (e.length == kUndefinedLength || e.valueAt + e.length > reader.size()) reader.fail();
        if (e.element == 0x0010 && e.length < 256) {
            std::string uid(e.length, '\0');
            reader.read(e.valueAt, reinterpret_cast<unsigned char*>(uid.data()), uid.size());
            transferSyntax = trimmed(uid);
        }
        at = e.valueAt + e.length;
    }
    return transferSyntax;
}

/// Without a transfer syntax, guess as GDCM does: explicit VR when the first
/// element's VR bytes are two capital letters.
bool looksExplicit(ElementReader& reader, std::uint64_t at) {
    unsigned char vr[2];
    reader.read(at + 4, vr, 2);
    return std::isupper(vr[0]) && std::isupper(vr[1]);
}

}  // namespace

void checkDicomStructure(const std::string& file) {
    ElementReader reader(file);
    std::uint64_t at = kDataAfterPreamble;
    const std::string transferSyntax = walkFileMeta(reader, at);
    if (transferSyntax == "1.2.840.10008.1.2.1.99") return;  // deflated: GDCM inflates it first
    if (at >= reader.size()) throw InputError(file, "truncated DICOM file: nothing follows its file meta information");
    Syntax syntax;
    if (transferSyntax == "1.2.840.10008.1.2") {
        syntax.explicitVr = false;
    } else if (transferSyntax == "1.2.840.10008.1.2.2") {
        syntax.bigEndian = true;
    } else if (transferSyntax.empty()) {
        syntax.explicitVr = looksExplicit(reader, at);
    }
    walk(reader, syntax, at, reader.size(), true, 0);
}

}  // namespace gvr
