#include "ImageFraming.h"

#include "Error.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

namespace gvr {

namespace {

constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
constexpr std::size_t kPngSignatureBytes = 8;

std::uint32_t bigEndian32(const std::string& bytes, std::size_t at) {
    return std::uint32_t(std::uint8_t(bytes[at])) << 24 | std::uint32_t(std::uint8_t(bytes[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(bytes[at + 2])) << 8 | std::uint32_t(std::uint8_t(bytes[at + 3]));
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
    }
}

}  // namespace gvr
