#include "render/Camera.h"

#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>

namespace gvr {

OrthoCamera makeCamera(const View& view, const std::array<openvdb::Vec3d, 8>& corners, int width, int height) {
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
        throw InputError("image size", "must be between 1x1 and " + std::to_string(kMaxImageSide) + "x" +
                                           std::to_string(kMaxImageSide) + " pixels");
    }
    // Beyond a bound, an angle is no longer a view a user means (6e307 degrees
    // overflowed in radians to a null direction, an internal error).
    if (!(std::abs(view.azimuthDeg) <= kMaxAngleDeg) || !(std::abs(view.elevationDeg) <= kMaxAngleDeg)) {
        throw InputError("`azimuth`/`elevation`", "angles must be finite numbers of degrees, at most 1e6 either way");
    }
    const double az = view.azimuthDeg * M_PI / 180.0, el = view.elevationDeg * M_PI / 180.0;
    OrthoCamera camera;
    camera.width = width;
    camera.height = height;
    camera.direction = -openvdb::Vec3d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    openvdb::Vec3d right = camera.direction.cross(openvdb::Vec3d(0, 0, 1));
    if (right.length() < 1e-9) right = openvdb::Vec3d(-std::cos(az), std::sin(az), 0.0);  // looking straight up or down
    camera.right = right.unit();
    camera.up = camera.right.cross(camera.direction).unit();
    camera.centre = openvdb::Vec3d(0.0);
    for (const auto& corner : corners) camera.centre += corner / 8.0;
    double halfRight = 0.0, halfUp = 0.0;
    for (const auto& corner : corners) {
        halfRight = std::max(halfRight, std::abs((corner - camera.centre).dot(camera.right)));
        halfUp = std::max(halfUp, std::abs((corner - camera.centre).dot(camera.up)));
    }
    // A 2 % margin, so the volume's silhouette never touches the border.
    camera.pixelMm = 1.02 * std::max(2.0 * halfRight / width, 2.0 * halfUp / height);
    if (!(camera.pixelMm > 0.0)) camera.pixelMm = 1.0;
    return camera;
}

std::array<openvdb::Vec3d, 8> worldCorners(const openvdb::math::Mat4d& worldFromIndex, const openvdb::CoordBBox& box) {
    std::array<openvdb::Vec3d, 8> corners;
    for (int c = 0; c < 8; ++c) {
        const openvdb::Vec3d index(c & 1 ? box.max().x() + 0.5 : box.min().x() - 0.5,
                                   c & 2 ? box.max().y() + 0.5 : box.min().y() - 0.5,
                                   c & 4 ? box.max().z() + 0.5 : box.min().z() - 0.5);
        corners[c] = worldFromIndex.transform(index);
    }
    return corners;
}

double angleBetweenDeg(const openvdb::Vec3d& a, const openvdb::Vec3d& b) {
    return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace gvr
