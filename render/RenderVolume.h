/// @file RenderVolume.h
/// @brief What the renderers draw: a Gaussian field or a VDB grid, in physical units.
#pragma once

#include "pipeline/GaussianAsset.h"
#include "pipeline/GaussianField.h"
#include "pipeline/LatticeSampler.h"
#include "pipeline/Trilinear.h"
#include "pipeline/ValueMapping.h"
#include "render/TransferPresets.h"

#include <openvdb/openvdb.h>

#include <array>
#include <memory>
#include <mutex>
#include <type_traits>
#include <vector>

namespace gvr {

/// Samples one volume at the voxel centres of one lattice, block by block.
class BlockSource {
public:
    virtual ~BlockSource() = default;
    /// Origins of the 8^3 blocks that may hold anything but background.
    virtual std::vector<openvdb::Coord> occupiedBlocks() const = 0;
    /// Writes physical values (channels per voxel, at blockOffset()) for the lattice
    /// voxels of the block at @a origin. Thread-safe.
    /// @return the voxels written: the block's part of the lattice.
    virtual openvdb::CoordBBox sampleBlock(const openvdb::Coord& origin, float* values) const = 0;
    /// Gaussians evaluated to sample the lattice: 0 for grids, and for a Gaussian
    /// volume whose voxels an earlier build evaluated.
    virtual std::size_t gaussiansReaching() const { return 0; }
};

/// The most samples a ray takes for each voxel it crosses, whatever spacing is asked:
/// enough for the finest a user may ask (0.05 voxels) of equal voxels. Past it, very
/// unequal voxels were sampled at their shortest edge along every axis: a ray along a
/// 1 mm edge of 1e-6 x 1 x 1 mm voxels took a million samples a voxel.
constexpr double kMostSamplesPerVoxelCrossed = 32.0;

class RenderVolume {
public:
    virtual ~RenderVolume() = default;

    virtual int channels() const = 0;
    /// The values at the volume's voxels, in physical units: a float (grey) or Vec3s
    /// (RGB) grid, which both renderers sample trilinearly between voxel centres.
    virtual const openvdb::GridBase& voxels() const = 0;
    /// Trilinear samples of voxels() on @a lattice.
    /// @param invisibleUpTo  values (luminance for RGB) up to this are transparent:
    ///                       a source may leave blocks that stay below it empty
    virtual std::unique_ptr<BlockSource> blocksOn(const Lattice& lattice, double invisibleUpTo) const;
    /// The same for a coarse preview, which must not wait for voxels() to be
    /// evaluated: a Gaussian volume samples its Gaussians at the lattice's points.
    virtual std::unique_ptr<BlockSource> previewBlocksOn(const Lattice& lattice, double invisibleUpTo) const {
        return blocksOn(lattice, invisibleUpTo);
    }
    /// A sample of the content's values (luminance for RGB), for percentile windows.
    /// Gathered on first use and kept: a Gaussian volume evaluates its field for it,
    /// and a viewer asks again at each change of preset. Thread-safe.
    const VolumeStatistics& statistics() const;
    /// What empty space holds, in physical units: channels() values.
    virtual std::array<float, 3> background() const = 0;
    /// background()'s value, or its luminance for RGB.
    double backgroundKey() const;

    const openvdb::math::Mat4d& worldFromIndex() const { return mWorldFromIndex; }
    const openvdb::CoordBBox& box() const { return mBox; }  ///< the volume's voxels, index space
    /// The shortest voxel edge in mm: one voxel of slice spacing and of opacity.
    double voxelMm() const;
    /// The finest step, in voxels (voxelMm()), worth taking along @a direction: a line
    /// along it crosses a voxel face every so often (more often across short edges),
    /// and meets kMostSamplesPerVoxelCrossed samples between two at this step.
    double finestStepVoxels(const openvdb::Vec3d& direction) const;
    /// What RGB data divide by to become colours in [0, 1]: the brightest channel value.
    double valueMax() const { return mValueMax; }

protected:
    /// What statistics() keeps.
    virtual VolumeStatistics gatherStatistics() const = 0;

    openvdb::math::Mat4d mWorldFromIndex = openvdb::math::Mat4d::identity();
    openvdb::CoordBBox mBox;
    double mValueMax = 1.0;

private:
    mutable std::once_flag mStatisticsGathered;
    mutable VolumeStatistics mStatistics;
};

/// A fitted Gaussian field, drawn as its export is: the field at the source's voxels,
/// evaluated on first use and kept, and between them trilinear like a grid's. The
/// Gaussians were fitted to the voxels' values; between voxels they depart from the
/// interpolation of those values, and a stack sampling them there departed from the
/// export (docs/benchmarks.md, "Assets drawn from their voxels").
/// Gaussians thinner than @a minScaleVoxels along an axis are widened to it with
/// their amplitude lowered so that their integral (their mass) stays: sheets and
/// needles thinner than a voxel then neither vanish between voxels nor flicker.
class GaussianRenderVolume : public RenderVolume {
public:
    /// @param foregroundAbove  values (luminance for RGB) above this are content, as
    ///                         the source's active voxels were: what statistics() samples
    GaussianRenderVolume(const GaussianParameters& params, float cutoffSigmas,
                         const openvdb::math::Mat4d& worldFromIndex, const openvdb::Vec3i& dims,
                         const ValueMapping& mapping, double valueMax, double foregroundAbove,
                         float minScaleVoxels = 0.5f);
    /// The asset's Gaussians, placed, mapped and thresholded as its source was.
    explicit GaussianRenderVolume(const GaussianAsset& asset, float minScaleVoxels = 0.5f);

    int channels() const override { return mField.channels(); }
    /// Every voxel some Gaussian reaches is active; the first call evaluates them on
    /// all cores. Thread-safe.
    const openvdb::GridBase& voxels() const override;
    /// Reports the Gaussians evaluated (gaussiansReaching()) on the call that evaluated voxels().
    std::unique_ptr<BlockSource> blocksOn(const Lattice& lattice, double invisibleUpTo) const override;
    /// Samples the Gaussians at the lattice's points (those that could be seen).
    std::unique_ptr<BlockSource> previewBlocksOn(const Lattice& lattice, double invisibleUpTo) const override;
    std::array<float, 3> background() const override;

protected:
    VolumeStatistics gatherStatistics() const override;

private:
    /// Evaluates voxels() unless done. @return the Gaussians evaluated: 0 when done before.
    std::size_t evaluateVoxelsOnce() const;

    GaussianField mField;
    ValueMapping mMapping;
    double mForegroundAbove;
    mutable std::once_flag mVoxelsEvaluated;
    mutable openvdb::GridBase::Ptr mVoxels;
};

/// Channel @a c of a grid value, grey or RGB.
inline double channelOf(float value, int) { return value; }
inline double channelOf(const openvdb::Vec3s& value, int c) { return value[c]; }

/// A float (grey) or Vec3s (RGB) grid, sampled trilinearly between voxel centres.
class GridRenderVolume : public RenderVolume {
public:
    /// @throw InputError naming the grid for other value types.
    explicit GridRenderVolume(openvdb::GridBase::ConstPtr grid);

    int channels() const override { return mColour ? 3 : 1; }
    const openvdb::GridBase& voxels() const override { return *mGrid; }
    /// What inactive voxels hold.
    std::array<float, 3> background() const override;
    /// Trilinear value at index-space point @a x into out[0..channels).
    template <typename Accessor>
    static void trilinear(const Accessor& accessor, const openvdb::Vec3d& x, float* out);

protected:
    VolumeStatistics gatherStatistics() const override;

private:
    openvdb::GridBase::ConstPtr mGrid;
    openvdb::FloatGrid::ConstPtr mFloat;
    openvdb::Vec3SGrid::ConstPtr mColour;
};

template <typename Accessor>
void GridRenderVolume::trilinear(const Accessor& accessor, const openvdb::Vec3d& x, float* out) {
    using ValueT = typename Accessor::ValueType;
    using LeafT = typename std::remove_const_t<typename Accessor::TreeType>::LeafNodeType;
    constexpr int channels = std::is_same_v<ValueT, openvdb::Vec3s> ? 3 : 1;
    const openvdb::Coord base = voxelBelow(x);
    ValueT corners[8];
    constexpr int last = int(LeafT::DIM) - 1;
    if ((base.x() & last) != last && (base.y() & last) != last && (base.z() & last) != last) {
        // The eight corners share a leaf (seven times in eight along each axis): one
        // probe and the leaf's own array, not eight trips through the tree.
        const LeafT* leaf = accessor.probeConstLeaf(base);
        if (!leaf) {  // a tile: one value all around
            const ValueT tile = accessor.getValue(base);
            for (int c = 0; c < channels; ++c) out[c] = float(channelOf(tile, c));
            return;
        }
        const ValueT* values = leaf->buffer().data() + LeafT::coordToOffset(base);
        constexpr int dim = int(LeafT::DIM);
        for (int n = 0; n < 8; ++n) corners[n] = values[(n >> 2) * dim * dim + (n >> 1 & 1) * dim + (n & 1)];
    } else {
        for (int n = 0; n < 8; ++n) corners[n] = accessor.getValue(base.offsetBy(n >> 2, n >> 1 & 1, n & 1));
    }
    blendTrilinearCorners(corners, x - base.asVec3d(), out);
}

}  // namespace gvr
