/// @file LowerCase.h
/// @brief Names that users type in any case: extensions, presets, structures.
#pragma once

#include <algorithm>
#include <cctype>
#include <string>

namespace gvr {

/// @a text with ASCII letters in lower case.
inline std::string lowerCase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

/// Whether @a text ends in @a suffix, ignoring case.
inline bool endsWithIgnoringCase(const std::string& text, const std::string& suffix) {
    return text.size() >= suffix.size() && lowerCase(text.substr(text.size() - suffix.size())) == lowerCase(suffix);
}

}  // namespace gvr
