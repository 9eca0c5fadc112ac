/// @file JsonNumber.h
/// @brief Figures in JSON output, where a perfect match has an infinite PSNR.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>

namespace gvr {

/// A number, or the string "inf" (JSON has no infinity; Python's float() reads it).
inline nlohmann::json jsonNumber(double value) {
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    return value;
}

}  // namespace gvr
