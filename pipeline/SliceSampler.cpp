#include "pipeline/SliceSampler.h"

#include <cmath>
#include <random>

namespace gvr {

std::vector<std::array<float, 3>> drawSlicePoints(const openvdb::CoordBBox& box, std::size_t pixels,
                                                  std::uint64_t seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const openvdb::Vec3d lower = box.min().asVec3d(), upper = box.max().asVec3d();
    const openvdb::Vec3d extent = upper - lower;

    openvdb::Vec3d centre;
    for (int axis = 0; axis < 3; ++axis) centre[axis] = lower[axis] + unit(random) * extent[axis];
    // Uniform direction on the sphere from a normalised Gaussian vector.
    std::normal_distribution<double> gaussian;
    openvdb::Vec3d normal(gaussian(random), gaussian(random), gaussian(random));
    if (normal.length() < 1e-9) normal = openvdb::Vec3d(0, 0, 1);
    normal.normalize();
    const openvdb::Vec3d helper = std::abs(normal.x()) < 0.9 ? openvdb::Vec3d(1, 0, 0) : openvdb::Vec3d(0, 1, 0);
    const openvdb::Vec3d u = normal.cross(helper).unitSafe();
    const openvdb::Vec3d v = normal.cross(u);

    // A square of the box's diagonal around the centre covers the plane's section.
    const double half = extent.length() * 0.5 + 0.5;
    std::vector<std::array<float, 3>> points;
    points.reserve(pixels);
    for (std::size_t p = 0; p < pixels; ++p) {
        const openvdb::Vec3d x = centre + u * (2.0 * unit(random) - 1.0) * half + v * (2.0 * unit(random) - 1.0) * half;
        if ((x.x() < lower.x() || x.y() < lower.y() || x.z() < lower.z()) ||
            (x.x() > upper.x() || x.y() > upper.y() || x.z() > upper.z())) {
            continue;
        }
        points.push_back({float(x.x()), float(x.y()), float(x.z())});
    }
    if (points.empty()) points.push_back({float(centre.x()), float(centre.y()), float(centre.z())});
    return points;
}

}  // namespace gvr
