/// @file VolumeTarget.h
/// @brief The volume a fit approximates, read from an ingested grid in normalised units.
#pragma once

#include "pipeline/Block.h"
#include "pipeline/Taper.h"
#include "pipeline/ValueMapping.h"

#include <openvdb/openvdb.h>

#include <bitset>
#include <functional>
#include <optional>

namespace gvr {

/// Reads a float "density" or Vec3s "color" grid (as ingest writes them) at voxels
/// or trilinearly, in normalised units: 0 = background, 1 = top of the data range.
/// The sampled domain is the source's full box (inactive voxels read as background).
class VolumeTarget {
public:
    /// @param region  if given, fit only these voxels (clipped to the source's box),
    ///                e.g. one structure's bounding box
    /// @param taper   if given, values are weighted by it: a brick's share of the volume
    /// @throw InputError naming @a name when the grid is neither float nor Vec3s.
    VolumeTarget(openvdb::GridBase::ConstPtr grid, const std::string& name,
                 const std::optional<openvdb::CoordBBox>& region = std::nullopt,
                 const std::optional<Taper>& taper = std::nullopt);

    int channels() const { return mChannels; }
    /// The voxels fitted: the source volume's box in index space (or the region).
    const openvdb::CoordBBox& box() const { return mBox; }
    std::uint64_t voxelCount() const { return mBox.volume(); }
    const ValueMapping& mapping() const { return mMapping; }
    /// Normalised data range (max - min over the source), the PSNR peak.
    double peak() const { return mPeak; }
    const openvdb::GridBase& grid() const { return *mGrid; }

    void valueAt(const openvdb::Coord& ijk, float* out) const;
    /// The 8^3 block at @a origin (a multiple of 8 on every axis, as OpenVDB leaves
    /// are) into out[channels() * offset], offsets as openvdb::tree::LeafNode numbers
    /// voxels: what valueAt() gives at each, read a leaf at a time.
    void blockValues(const openvdb::Coord& origin, float* out) const;
    bool isActive(const openvdb::Coord& ijk) const;
    /// isActive() for every voxel of the block at @a origin, at blockOffset().
    std::bitset<kBlockVoxels> blockActive(const openvdb::Coord& origin) const;
    /// Trilinear interpolation between voxel centres at index-space point @a x.
    void trilinearAt(const float x[3], float* out) const;

    /// Calls @a visit for every active voxel inside box(), in a fixed order.
    void forEachActiveVoxel(const std::function<void(const openvdb::Coord&)>& visit) const;
    /// Active voxels inside box().
    std::uint64_t activeVoxelCount() const { return mActiveVoxels; }
    /// Active voxels inside @a region, leaf by leaf.
    std::uint64_t activeVoxelCount(const openvdb::CoordBBox& region) const;

    /// Normalised central-difference gradient magnitude at a voxel (first channel
    /// for grey, luminance for RGB).
    float gradientMagnitude(const openvdb::Coord& ijk) const;
    /// gradientMagnitude() of every voxel of the block at @a origin (a multiple of 8)
    /// into out[blockOffset()], the same floats, reading the block once and the
    /// neighbours beyond its faces through one cached accessor.
    void blockGradientMagnitudes(const openvdb::Coord& origin, float* out) const;

private:
    /// Kept out of valueAt(), which every fit calls for every sample.
    void applyTaper(const openvdb::Coord& ijk, float* out) const;

    /// valueAt() read through @a source: a grid's tree, or an accessor of it that
    /// caches the path to the last leaf for a run of nearby reads.
    template <typename TreeOrAccessor>
    void normalisedValue(const TreeOrAccessor& source, const openvdb::Coord& ijk, float* out) const;

    openvdb::GridBase::ConstPtr mGrid;
    openvdb::FloatGrid::ConstPtr mFloat;
    openvdb::Vec3SGrid::ConstPtr mColour;
    int mChannels = 1;
    openvdb::CoordBBox mBox;
    ValueMapping mMapping;
    double mPeak = 1.0;
    std::uint64_t mActiveVoxels = 0;
    std::optional<Taper> mTaper;
};

}  // namespace gvr
