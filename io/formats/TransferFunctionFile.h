/// @file TransferFunctionFile.h
/// @brief Custom transfer functions as small JSON files.
///
/// A file holds piecewise-linear RGBA control points over a scalar in physical
/// units (HU for CT, intensity for MRI, luminance for RGB data):
///
///     {"points": [[-1000, 0, 0, 0, 0], [300, 1, 0.9, 0.8, 0.6], [1500, 1, 1, 1, 1]]}
///
/// Each point is [value, r, g, b, a]; values increase, and r, g, b, a lie in [0, 1].
#pragma once

#include "pipeline/TransferFunction.h"

#include <string>

namespace gvr {

/// @throw InputError naming @a path when it is missing, not JSON, or breaks the rules above.
TransferFunction readTransferFunction(const std::string& path);

/// Writes @a tf in the format above, atomically, so that a preset can be reused
/// unchanged on other volumes (e.g. every method of a benchmark).
void writeTransferFunction(const std::string& path, const TransferFunction& tf);

}  // namespace gvr
