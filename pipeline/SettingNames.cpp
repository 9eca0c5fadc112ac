#include "pipeline/SettingNames.h"

namespace gvr {

namespace {

bool isKey(const std::string& text) {
    if (text.empty() || !(text[0] >= 'a' && text[0] <= 'z')) return false;
    for (char c : text) {
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
    }
    return true;
}

}  // namespace

std::string respellSettings(const std::string& message, const SettingSpelling& spell) {
    std::string out;
    std::size_t from = 0;
    for (std::size_t open = message.find('`'); open != std::string::npos; open = message.find('`', from)) {
        const std::size_t close = message.find('`', open + 1);
        if (close == std::string::npos) break;
        const std::string inside = message.substr(open + 1, close - open - 1);
        const std::size_t equals = inside.find('=');
        const std::string key = inside.substr(0, equals);
        out += message.substr(from, open - from);
        if (isKey(key)) {
            out += spell(key, equals == std::string::npos ? "" : inside.substr(equals + 1));
            from = close + 1;
        } else {  // not ours: keep the backquote, and look again from the next one
            out += '`';
            from = open + 1;
        }
    }
    return out + message.substr(from);
}

}  // namespace gvr
