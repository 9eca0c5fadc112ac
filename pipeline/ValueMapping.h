/// @file ValueMapping.h
/// @brief How normalised fit values map back to physical units (HU, intensity, RGB).
#pragma once

#include <algorithm>
#include <array>
#include <cfloat>

namespace gvr {

/// physical_c = offset[c] + scale * normalised_c. Normalised 0 is the background
/// (what inactive voxels stand for) and 1 the top of the data range.
struct ValueMapping {
    std::array<double, 3> offset{0.0, 0.0, 0.0};
    double scale = 1.0;

    double toPhysical(double normalised, int channel) const { return offset[channel] + scale * normalised; }
    double toNormalised(double physical, int channel) const { return (physical - offset[channel]) / scale; }
    /// As stored in a float grid: saturated at the float range, never infinite.
    float toPhysicalFloat(double normalised, int channel) const {
        return float(std::clamp(toPhysical(normalised, channel), -double(FLT_MAX), double(FLT_MAX)));
    }
};

}  // namespace gvr
