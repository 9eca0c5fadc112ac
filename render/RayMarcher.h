/// @file RayMarcher.h
/// @brief The reference renderer: rays marched through a grid, sampled trilinearly
/// at most half a voxel apart, with the same classification and compositing as
/// shear-warp. Where the classification makes the background transparent, empty
/// space is skipped where the VDB tree has no active leaf or tile; otherwise every
/// sample inside the volume's cells is taken.
#pragma once

#include "render/Camera.h"
#include "render/Classifier.h"
#include "render/Framebuffer.h"
#include "render/RenderVolume.h"

namespace gvr {

struct RayMarchSettings {
    double stepVoxels = 0.5;           ///< step along the ray, in voxels (the smallest edge); (0, 0.5]
    float terminationOpacity = 0.98f;  ///< a ray stops at this opacity
    /// n: n x n rays per pixel on a regular grid, averaged (a box filter). One ray
    /// aliases thin structures; 4 (kReferenceRaysPerSide) is the reference that
    /// render quality is measured against.
    int raysPerSide = 1;
};

/// The anti-aliased reference: 4 x 4 rays per pixel.
constexpr int kReferenceRaysPerSide = 4;
/// The most rays per pixel side a render takes (256 rays a pixel).
constexpr int kMaxRaysPerSide = 16;

/// @throw InputError when settings.raysPerSide is outside 1..kMaxRaysPerSide.
/// Marches through volume.voxels(): for a Gaussian volume, the field at its voxels,
/// as its export holds it.
Framebuffer rayMarch(const RenderVolume& volume, const Classifier& classifier, const OrthoCamera& camera,
                     const RayMarchSettings& settings);

}  // namespace gvr
