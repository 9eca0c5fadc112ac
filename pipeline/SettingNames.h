/// @file SettingNames.h
/// @brief How the library's messages name a setting, so that each front end can say
/// it in its own words.
///
/// A message names a setting by its key between backquotes, `nan_to`, or with a
/// value, `nan_to=VALUE`. The key is the snake_case name of the command line's flag
/// (--nan-to), which is also how Python spells most arguments. gvr prints
/// "--nan-to VALUE"; Python prints "nan_to=VALUE"; a C++ caller reads the key.
#pragma once

#include <functional>
#include <string>

namespace gvr {

/// Spells one setting: @a value is empty when the message gives none.
using SettingSpelling = std::function<std::string(const std::string& key, const std::string& value)>;

/// @a message with every `key` and `key=value` replaced by what @a spell returns.
/// Backquotes around anything else (not a lower-case key) are left as they are.
std::string respellSettings(const std::string& message, const SettingSpelling& spell);

}  // namespace gvr
