#include "io/asset/ZstdFrame.h"

#include "io/guard/ByteOrder.h"

#include <zstd.h>

#include <cstdint>
#include <stdexcept>

namespace gvr {

void appendZstdFrame(std::string& out, std::string_view plain, int level) {
    std::string frame(ZSTD_compressBound(plain.size()), '\0');
    const std::size_t size = ZSTD_compress(frame.data(), frame.size(), plain.data(), plain.size(), level);
    if (ZSTD_isError(size)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(size));
    appendLittleEndian(out, std::uint32_t(size));
    out.append(frame.data(), size);
}

std::string takeZstdFrame(std::string_view body, std::size_t& cursor, std::size_t expectedBytes, const char* what) {
    if (body.size() - cursor < sizeof(std::uint32_t)) throw std::runtime_error(std::string(what) + ": cut short");
    const auto length = loadLittleEndian<std::uint32_t>(body.data() + cursor);
    cursor += sizeof length;
    if (length > body.size() - cursor) throw std::runtime_error(std::string(what) + ": runs past the end of the body");
    const char* frame = body.data() + cursor;
    if (ZSTD_getFrameContentSize(frame, length) != expectedBytes) {
        throw std::runtime_error(std::string(what) + ": does not hold the bytes its header says");
    }
    std::string plain(expectedBytes, '\0');
    const std::size_t size = ZSTD_decompress(plain.data(), expectedBytes, frame, length);
    if (ZSTD_isError(size) || size != expectedBytes)
        throw std::runtime_error(std::string(what) + ": does not decompress");
    cursor += length;
    return plain;
}

}  // namespace gvr
