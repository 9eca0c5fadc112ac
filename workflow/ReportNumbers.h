/// @file ReportNumbers.h
/// @brief Figures as gvr writes them, in JSON and in text, where a perfect match
/// has an infinite PSNR.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace gvr {

/// A number, or null where it is not finite (the PSNR of a perfect match): JSON has
/// no infinity, and a string in a number's place breaks a reader that sums columns.
inline nlohmann::json jsonNumber(double value) {
    if (!std::isfinite(value)) return nullptr;
    return value;
}

/// Decibels to two places, "38.12", or "inf" for a perfect match.
inline std::string formatDb(double db) {
    if (std::isinf(db)) return db > 0 ? "inf" : "-inf";
    std::ostringstream out;
    out << std::fixed << std::setprecision(2) << db;
    return out.str();
}

}  // namespace gvr
