/// @file JsonText.h
/// @brief JSON as gvr writes it: every string UTF-8, whatever bytes a name held.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace gvr {

/// @a value as JSON text (indented by @a indent spaces; -1: on one line). A byte
/// that is not UTF-8, as a Linux file name may hold, is written as U+FFFD where
/// nlohmann::json::dump would throw.
std::string jsonText(const nlohmann::json& value, int indent = -1);

/// True when @a text is well-formed UTF-8 (no overlong forms, surrogates or code
/// points beyond U+10FFFF).
bool isUtf8(std::string_view text);

}  // namespace gvr
