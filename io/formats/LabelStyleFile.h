/// @file LabelStyleFile.h
/// @brief Per-structure colour and opacity overrides as a small JSON file:
///
///     {"Hippocampus_L": {"color": [1, 0.2, 0.2]}, "77": {"opacity": 0.3}}
///
/// Keys are structure names or ids; "color" is RGB in [0, 1], "opacity" a factor
/// (>= 0) on the transfer function's opacity.
#pragma once

#include "pipeline/LabelStyle.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace gvr {

/// @return styles by the key as written (resolve names and ids with selectLabels).
/// @throw InputError naming @a path for anything else.
std::map<std::string, LabelStyle> readLabelStyles(const std::string& path);

/// The styles of a JSON object as the file holds it (Python's dict of them).
/// @throw InputError naming @a name, as readLabelStyles.
std::map<std::string, LabelStyle> parseLabelStyles(const nlohmann::json& styles, const std::string& name);

}  // namespace gvr
