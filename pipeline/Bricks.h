/// @file Bricks.h
/// @brief Fitting a volume in bricks: each brick is fitted on its own, so that
/// bricks can run in other processes or on other machines, and the results are
/// merged into one set of Gaussians.
///
/// The volume's box is cut into a lattice of bricks whose faces lie on OpenVDB
/// leaf boundaries (multiples of 8 in index space), so a brick reads whole leaves.
/// The bricks overlap by a halo on each side of a face, where each one fits the
/// volume weighted by a taper (Taper.h) that fades it out across the face. The
/// tapers of all bricks add up to one, so the merged field, the sum of all
/// bricks' Gaussians, approximates the volume across the faces as well as inside:
/// no Gaussian has to match a neighbour that was fitted apart from it.
#pragma once

#include "pipeline/Fitter.h"

#include <openvdb/openvdb.h>

#include <array>
#include <vector>

namespace gvr {

/// Voxels on each side of a face between bricks over which their tapers fade: the
/// narrowest seams of the widths measured (README, "Larger than one machine").
constexpr int kDefaultBrickHalo = 4;

struct Brick {
    std::size_t index = 0;
    openvdb::CoordBBox volume;  ///< the whole volume's box, which the cores tile
    openvdb::CoordBBox core;    ///< the voxels where the brick's taper is at least 1/2
    openvdb::CoordBBox fitted;  ///< core plus halo, clipped to the volume's box
    int halo = 0;
    std::uint64_t coreActiveVoxels = 0;
    std::size_t budget = 0;  ///< Gaussians

    Taper taper() const { return {core, volume, halo}; }
};

/// Bricks along x, y and z whose product is @a count, chosen so that the bricks are
/// as near cubes as the leaf lattice of @a box allows (the least halo per voxel).
/// @throw InputError naming `bricks` when @a box has fewer leaves than @a count
///        along every way of splitting it.
openvdb::Coord brickLattice(const openvdb::CoordBBox& box, std::size_t count);

/// The bricks of @a target.box() on @a lattice, in x-fastest order, with their
/// active voxels counted and exactly @a total Gaussians split among them in
/// proportion to the active voxels of their cores.
std::vector<Brick> planBricks(const VolumeTarget& target, const openvdb::Coord& lattice, int halo, std::size_t total);

/// The voxels within @a width voxels of a face between two of @a bricks (a plan's
/// bricks, which tile their volume): where a seam would show.
class BrickSeams {
public:
    BrickSeams(const std::vector<Brick>& bricks, int width);
    bool near(const openvdb::Coord& ijk) const;

private:
    std::array<std::vector<int>, 3> mCuts;  ///< first voxel of each brick after the first, per axis
    int mWidth;
};

/// Fits brick.budget Gaussians to @a grid over the brick's fitted box, weighted by
/// its taper, with a seed of its own (settings.seed and the brick's index). The
/// samples per iteration (voxels, slice pixels, held-out voxels) are the brick's
/// share of settings' by volume. settings.gaussians is ignored.
GaussianParameters fitBrick(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const Brick& brick,
                            const FitSettings& settings, const FitObserver& observer = {}, FitReport* report = nullptr);

}  // namespace gvr
