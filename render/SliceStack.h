/// @file SliceStack.h
/// @brief One stack of classified slices through a volume, perpendicular to a
/// stack direction: what shear-warp builds once and composites for many views.
///
/// Slices are sampled on a lattice in world space (pixelMm across, sliceMm apart),
/// so any stack direction works, not only the volume's axes. Each sample holds
/// premultiplied colour and the opacity of one slice spacing, 16 bits each; each
/// slice row keeps only its runs of visible samples (Lacroute's run-length
/// encoding), which is how compositing skips empty space, inside the body too.
#pragma once

#include "Classifier.h"
#include "Progress.h"
#include "RenderVolume.h"

#include <cstdint>
#include <vector>

namespace gvr {

struct StackGeometry {
    openvdb::Vec3d normal, e1, e2;  ///< unit, world; slices are perpendicular to normal
    openvdb::Vec3d origin;          ///< world position of sample (0, 0) of slice 0, the front
    double pixelMm = 1.0, sliceMm = 1.0;
    int width = 0, height = 0, slices = 0;

    /// The sample lattice: index (i, j, k) is sample (i, j) of slice k.
    Lattice lattice() const;
};

struct StackSample {
    std::uint16_t r = 0, g = 0, b = 0, a = 0;  ///< premultiplied colour and opacity, x 65535
};

/// Transparent gaps shorter than this many samples stay inside a run: a run costs
/// more to step over than a few empty samples cost to composite.
constexpr int kRunGap = 4;

/// A run is stored with one transparent sample on either side, so that resampling
/// may read a run's neighbours without a test.
struct RowRun {
    std::uint32_t begin = 0, end = 0;  ///< samples [begin, end) of the row are stored
    std::uint32_t offset = 0;          ///< where sample `begin` sits in Slice::samples
};

struct Slice {
    /// Row j's runs are runs[rowRuns[j]] up to runs[rowRuns[j + 1]], left to right;
    /// every sample outside them is transparent.
    std::vector<std::uint32_t> rowRuns;
    std::vector<RowRun> runs;
    std::vector<StackSample> samples;
};

/// One volume and how to classify it. A stack may hold several layers that share
/// the first one's place in the world: the structures of one asset, each with its
/// own style.
struct StackLayer {
    const RenderVolume* volume = nullptr;
    Classifier classifier;
};

class SliceStack {
public:
    /// Samples @a volume on the stack's lattice (in parallel over 8^3 blocks, only
    /// where the volume has content) and classifies every sample, with the opacity
    /// corrected from one voxel to one slice spacing: 1 - (1 - alpha)^(sliceMm / voxelMm).
    SliceStack(const RenderVolume& volume, const Classifier& classifier, const openvdb::Vec3d& direction,
               double sliceSpacingVoxels, double pixelMm, const ProgressFn& progress = {});

    /// The same for several layers: where layers meet, their opacities combine as
    /// 1 - prod(1 - alpha) and their colours in proportion to their opacities.
    SliceStack(const std::vector<StackLayer>& layers, const openvdb::Vec3d& direction, double sliceSpacingVoxels,
               double pixelMm, const ProgressFn& progress = {});

    const StackGeometry& geometry() const { return mGeometry; }
    const std::vector<Slice>& slices() const { return mSlices; }
    /// Gaussians the build evaluated (0 for grids).
    std::size_t gaussiansTouched() const { return mGaussiansTouched; }

private:
    StackGeometry mGeometry;
    std::vector<Slice> mSlices;
    std::size_t mGaussiansTouched = 0;
};

}  // namespace gvr
