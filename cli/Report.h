/// @file Report.h
/// @brief How commands print figures: decibels, infinities in JSON, memory.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace gvr {

/// "38.12", or "inf" for a perfect match.
std::string formatDb(double db);

/// A number, or the string "inf" (JSON has no infinity; Python's float() reads it).
nlohmann::json jsonNumber(double value);

/// Peak resident memory of this process so far, in MiB.
double peakRssMiB();

}  // namespace gvr
