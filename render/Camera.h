/// @file Camera.h
/// @brief An orthographic camera that orbits the centre of a volume.
#pragma once

#include <openvdb/openvdb.h>

#include <array>

namespace gvr {

/// Where the camera looks from. Azimuth turns about the world's superior axis (+z
/// in RAS); 0 looks from anterior (+y) at the face, with the patient's right on the
/// image's left (radiological). Elevation lifts the camera towards superior.
struct View {
    double azimuthDeg = 0.0;
    double elevationDeg = 0.0;
};

struct OrthoCamera {
    openvdb::Vec3d direction;  ///< unit, world: the way rays travel
    openvdb::Vec3d right, up;  ///< unit, world: the image's x and (upwards) y axes
    openvdb::Vec3d centre;     ///< world point seen at the image centre
    double pixelMm = 1.0;      ///< world size of one pixel
    int width = 0, height = 0;

    /// The world point on the plane through centre, normal to direction, at the
    /// centre of pixel (x, y); y grows downwards.
    openvdb::Vec3d pixelPoint(double x, double y) const {
        return centre + right * ((x + 0.5 - 0.5 * width) * pixelMm) - up * ((y + 0.5 - 0.5 * height) * pixelMm);
    }
};

/// The largest angle a camera takes either way, in degrees (2,778 turns).
constexpr double kMaxAngleDeg = 1e6;

/// The largest image side a camera takes, in pixels: the command line and Python
/// check sizes against it before any work.
constexpr int kMaxImageSide = 8192;

/// A camera of @a width x @a height pixels that sees all of the world box whose
/// corners are @a corners from @a view, with a 2 % margin on its tighter axis.
/// @throw InputError when a size is outside 1..kMaxImageSide or an angle is not
/// finite or beyond kMaxAngleDeg.
OrthoCamera makeCamera(const View& view, const std::array<openvdb::Vec3d, 8>& corners, int width, int height);

/// The eight world corners of the voxel cells of @a box (index -0.5 to max + 0.5).
std::array<openvdb::Vec3d, 8> worldCorners(const openvdb::math::Mat4d& worldFromIndex, const openvdb::CoordBBox& box);

/// Angle between two unit directions, in degrees.
double angleBetweenDeg(const openvdb::Vec3d& a, const openvdb::Vec3d& b);

}  // namespace gvr
