#include "io/formats/JsonText.h"

namespace gvr {

std::string jsonText(const nlohmann::json& value, int indent) {
    return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

bool isUtf8(std::string_view text) {
    std::size_t k = 0;
    while (k < text.size()) {
        const unsigned char lead = static_cast<unsigned char>(text[k]);
        std::size_t length = 0;
        char32_t point = 0, least = 0;
        if (lead < 0x80) {
            ++k;
            continue;
        }
        if ((lead & 0xE0) == 0xC0) {
            length = 2, point = lead & 0x1F, least = 0x80;
        } else if ((lead & 0xF0) == 0xE0) {
            length = 3, point = lead & 0x0F, least = 0x800;
        } else if ((lead & 0xF8) == 0xF0) {
            length = 4, point = lead & 0x07, least = 0x10000;
        } else {
            return false;
        }
        if (k + length > text.size()) return false;
        for (std::size_t c = 1; c < length; ++c) {
            const unsigned char next = static_cast<unsigned char>(text[k + c]);
            if ((next & 0xC0) != 0x80) return false;
            point = (point << 6) | (next & 0x3F);
        }
        if (point < least || point > 0x10FFFF || (point >= 0xD800 && point <= 0xDFFF)) return false;
        k += length;
    }
    return true;
}

}  // namespace gvr
