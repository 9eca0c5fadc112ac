#include "pipeline/Taper.h"

#include <cmath>

namespace gvr {

namespace {

/// sin^2(pi/2 t) over t clamped to [0, 1]: smooth, and s(t) + s(1 - t) = 1.
float fadeIn(double t) {
    // Most voxels of a brick lie outside its fading bands: no sine for them.
    if (t <= 0.0) return 0.0f;
    if (t >= 1.0) return 1.0f;
    const double s = std::sin(0.5 * M_PI * t);
    return float(s * s);
}

}  // namespace

float Taper::at(const openvdb::Coord& ijk) const {
    if (width <= 0) return core.isInside(ijk) ? 1.0f : 0.0f;
    const double span = 2.0 * width;
    float weight = 1.0f;
    for (int a = 0; a < 3; ++a) {
        const double x = ijk[a];
        if (core.min()[a] > volume.min()[a]) weight *= fadeIn((x - core.min()[a] + width + 0.5) / span);
        if (core.max()[a] < volume.max()[a]) weight *= fadeIn((core.max()[a] + width + 0.5 - x) / span);
    }
    return weight;
}

}  // namespace gvr
