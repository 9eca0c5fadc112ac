#include "io/formats/LabelStyleFile.h"

#include "io/guard/InputFile.h"
#include "pipeline/Error.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace gvr {

namespace {

constexpr double kMaxOpacityScale = 1000.0;

LabelStyle parseStyle(const nlohmann::json& entry, const std::string& path, const std::string& key) {
    const std::string where = "structure '" + key + "'";
    if (!entry.is_object()) throw InputError(path, where + ": expected {\"color\": [r, g, b], \"opacity\": x}");
    LabelStyle style;
    for (const auto& [name, value] : entry.items()) {
        if (name == "color") {
            if (!value.is_array() || value.size() != 3) throw InputError(path, where + ": color must be [r, g, b]");
            std::array<float, 3> rgb{};
            for (int c = 0; c < 3; ++c) {
                if (!value[c].is_number() || !(value[c].get<double>() >= 0.0 && value[c].get<double>() <= 1.0)) {
                    throw InputError(path, where + ": color components must lie in [0, 1]");
                }
                rgb[c] = value[c].get<float>();
            }
            style.colour = rgb;
        } else if (name == "opacity") {
            // Bounded before the float cast; opacities are clamped to 1 after scaling anyway.
            if (!value.is_number() || !(value.get<double>() >= 0.0 && value.get<double>() <= kMaxOpacityScale)) {
                throw InputError(path, where + ": opacity must be a number in [0, 1000]");
            }
            style.opacity = value.get<float>();
        } else {
            throw InputError(path, where + ": unknown key '" + name + "' (color, opacity)");
        }
    }
    return style;
}

}  // namespace

std::map<std::string, LabelStyle> readLabelStyles(const std::string& path) {
    requireRegularFile(path);
    std::ifstream in(path);
    if (!in) throw InputError(path, "cannot open the label styles");
    return parseLabelStyles(nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false), path);
}

std::map<std::string, LabelStyle> parseLabelStyles(const nlohmann::json& styles, const std::string& name) {
    if (styles.is_discarded() || !styles.is_object()) throw InputError(name, "not a JSON object of structure styles");
    std::map<std::string, LabelStyle> parsed;
    for (const auto& [key, entry] : styles.items()) parsed[key] = parseStyle(entry, name, key);
    return parsed;
}

}  // namespace gvr
