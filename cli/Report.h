/// @file Report.h
/// @brief How commands print figures: decibels and memory (JSON numbers: JsonNumber.h).
#pragma once

#include "JsonNumber.h"

#include <nlohmann/json.hpp>

#include <string>

namespace gvr {

/// "38.12", or "inf" for a perfect match.
std::string formatDb(double db);

/// Peak resident memory of this process so far, in MiB.
double peakRssMiB();

}  // namespace gvr
