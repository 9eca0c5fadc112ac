/// @file VolPackReference.h
/// @brief Lacroute's VolPack rendering a dense 8-bit volume, timed: the benchmark's outside reference.
///
/// VolPack is the original shear-warp library (Lacroute & Levoy, SIGGRAPH '94). The benchmark
/// times it on the same volume as gvr's own shear-warp renderer, so the figures can be compared
/// with a known, independent implementation. Link with libvolpack (Debian: libvolpack1-dev).
#pragma once

#include <cstdint>
#include <vector>

namespace gvr {

/// A dense 8-bit scalar volume as VolPack takes it.
struct VolPackVolume {
    int nx = 0, ny = 0, nz = 0;
    std::vector<std::uint8_t> voxels;       ///< nx*ny*nz values, x fastest, then y, then z
    double spacingMm[3] = {1.0, 1.0, 1.0};  ///< voxel size along x, y, z
};

struct VolPackResult {
    double classifySeconds =
        0;  ///< building the classified (run-length encoded) volume, including gradient/normal computation
    double framesPerSecond = 0;  ///< renders of the classified volume, averaged over `frames` views
    int frames = 0;
    std::vector<std::uint8_t> lastImage;  ///< width*height luminance of the last frame, row 0 at the top
};

/// Renders with VolPack at width x height, orthographic, for `frames` views turning azimuth from 0
/// by `stepDeg` degrees about the volume's z axis (elevation fixed at `elevationDeg`),
/// single-threaded (VolPack has no threads). The camera follows gvr's OrthoCamera in the volume's
/// index axes: azimuth 0 looks from +y, azimuth turns towards +x, z is up in the image, and each
/// view's window fits the volume's projected corners with a 2 % margin. Spacing scales the model
/// matrix; VolPack's normals and gradient magnitudes stay in voxel units.
///
/// Classification: with @a opacityByValue (256 opacities per voxel, by 8-bit value), that
/// table alone, and every voxel above opacity 0 is kept, as gvr's stacks keep every
/// visible sample: the same classification as gvr's, for a like-for-like comparison.
/// Without it, a scalar opacity ramp from 0 at value 0 to 1 at value 24 (of 255),
/// multiplied by a gradient-magnitude ramp (VolPack's gradient-weighted classification,
/// as in its examples), minimum voxel opacity 0.05. Early ray termination at opacity
/// 0.95. Shading: one directional light, grey Phong material, VP_LUMINANCE image.
///
/// @throw std::invalid_argument if the volume, the image size or the table is unusable.
/// @throw std::runtime_error with VolPack's error string on failure.
VolPackResult renderWithVolPack(const VolPackVolume& volume, int width, int height, int frames, double stepDeg,
                                double elevationDeg, const std::vector<float>& opacityByValue = {});

}  // namespace gvr
