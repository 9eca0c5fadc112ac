#include "io/guard/ImageFraming.h"

#include "io/guard/ByteOrder.h"
#include "io/guard/TiffFraming.h"
#include "pipeline/Error.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

namespace gvr {

namespace {

constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
constexpr std::size_t kPngSignatureBytes = 8;

std::uint32_t bigEndian32(const std::string& bytes, std::size_t at) {
    return loadWord<std::uint32_t>(&bytes[at], true);
}
std::uint32_t littleEndian32(const std::string& bytes, std::size_t at) {
    return loadLittleEndian<std::uint32_t>(&bytes[at]);
}
std::uint32_t littleEndian16(const std::string& bytes, std::size_t at) {
    return loadLittleEndian<std::uint16_t>(&bytes[at]);
}

std::string readBytes(std::ifstream& in, std::streamoff from, std::streamoff count) {
    std::string bytes(std::size_t(count), '\0');
    in.seekg(from);
    in.read(bytes.data(), count);
    bytes.resize(std::size_t(in.gcount()));
    return bytes;
}

void checkPngChunks(const std::string& file, const std::string& bytes) {
    std::size_t at = kPngSignatureBytes;
    while (true) {
        if (bytes.size() - at < 12) throw InputError(file, "truncated PNG: it ends before its IEND chunk");
        const std::uint64_t length = bigEndian32(bytes, at);
        const std::string type = bytes.substr(at + 4, 4);
        if (length > bytes.size() - at - 12) {
            throw InputError(file, "truncated or corrupt PNG: chunk '" + type + "' runs past the end of the file");
        }
        const auto* typeAndData = reinterpret_cast<const Bytef*>(bytes.data() + at + 4);
        const uLong crc = crc32(crc32(0L, Z_NULL, 0), typeAndData, uInt(length + 4));
        if (crc != bigEndian32(bytes, at + 8 + length)) {
            throw InputError(file, "corrupt PNG: chunk '" + type + "' fails its CRC check");
        }
        if (type == "IEND") return;
        at += 12 + length;
    }
}

/// The end-of-image marker (FF D9) cannot occur inside entropy-coded data; a
/// little padding after it is tolerated.
void checkJpegEnd(const std::string& file, const std::string& tail) {
    if (tail.find("\xff\xd9") == std::string::npos) {
        throw InputError(file, "truncated JPEG: no end-of-image marker");
    }
}

/// OpenImageIO's BMP reader trusts the header: an RLE compression on a 24-bit
/// image made it read before its buffer (found by fuzz_image). Only uncompressed
/// pixels (BI_RGB, BI_BITFIELDS) of a standard depth are passed on, and only when
/// the file holds every row the header promises.
void checkBmpHeader(const std::string& file, const std::string& header, std::streamoff size) {
    if (header.size() < 26) throw InputError(file, "truncated BMP: its header is cut");
    const std::uint32_t infoBytes = littleEndian32(header, 14);
    const bool core = infoBytes == 12;  // OS/2 BITMAPCOREHEADER: 16-bit sizes, no compression field
    if (!core && (infoBytes < 40 || header.size() < 34)) throw InputError(file, "corrupt BMP: unknown header");
    // Signed: a negative height marks a top-down BMP. (Both branches as int64, or the
    // conditional's common type, uint32, would turn -2 rows into 4 billion.)
    const std::int64_t width =
        core ? std::int64_t(littleEndian16(header, 18)) : std::int64_t(std::int32_t(littleEndian32(header, 18)));
    const std::int64_t height =
        core ? std::int64_t(littleEndian16(header, 20)) : std::int64_t(std::int32_t(littleEndian32(header, 22)));
    const std::uint32_t bits = littleEndian16(header, core ? 24 : 28);
    const std::uint32_t compression = core ? 0 : littleEndian32(header, 30);
    const bool standardDepth = bits == 1 || bits == 4 || bits == 8 || bits == 16 || bits == 24 || bits == 32;
    if (!(compression == 0 && standardDepth) && !(compression == 3 && (bits == 16 || bits == 32))) {
        throw InputError(file, "unsupported BMP: " + std::to_string(bits) + " bits a pixel with compression " +
                                   std::to_string(compression) + "; gvr reads uncompressed BMP");
    }
    if (width <= 0 || height == 0) {
        throw InputError(file, "corrupt BMP: its size is " + std::to_string(width) + "x" + std::to_string(height));
    }
    const std::uint64_t rowBytes = (std::uint64_t(width) * bits + 31) / 32 * 4;
    const std::uint64_t needed = std::uint64_t(littleEndian32(header, 10)) + rowBytes * std::uint64_t(std::abs(height));
    if (needed > std::uint64_t(size)) {
        throw InputError(file, "truncated BMP: its pixels need " + std::to_string(needed) + " bytes, the file has " +
                                   std::to_string(size));
    }
}

}  // namespace

void checkImageFraming(const std::string& file) {
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    if (!in) throw InputError(file, "cannot open file");
    const std::streamoff size = in.tellg();
    const std::string head = readBytes(in, 0, std::min<std::streamoff>(size, kPngSignatureBytes));
    if (head.compare(0, kPngSignatureBytes, kPngSignature, kPngSignatureBytes) == 0) {
        checkPngChunks(file, readBytes(in, 0, size));  // the whole file: every chunk has a CRC
    } else if (head.compare(0, 2, "\xff\xd8") == 0) {
        const std::streamoff tail = std::min<std::streamoff>(size, 64);
        checkJpegEnd(file, readBytes(in, size - tail, tail));
    } else if (head.compare(0, 2, "BM") == 0) {
        checkBmpHeader(file, readBytes(in, 0, std::min<std::streamoff>(size, 34)), size);
    } else if (isTiffSignature(head)) {
        checkTiffFraming(file, in, std::uint64_t(size));
    }
}

}  // namespace gvr
