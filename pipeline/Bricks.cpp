#include "pipeline/Bricks.h"

#include "pipeline/Error.h"
#include "pipeline/LabelBudget.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gvr {

namespace {

constexpr int kLeafDim = 8;

int leafOf(int voxel) { return voxel >= 0 ? voxel / kLeafDim : -((-voxel + kLeafDim - 1) / kLeafDim); }

/// Leaves of @a box along each axis (partial leaves counted).
openvdb::Coord leafCounts(const openvdb::CoordBBox& box) {
    openvdb::Coord counts;
    for (int a = 0; a < 3; ++a) counts[a] = leafOf(box.max()[a]) - leafOf(box.min()[a]) + 1;
    return counts;
}

/// Voxels [first, last] of part @a part of @a parts along axis @a a: whole leaves,
/// clipped to @a box.
std::pair<int, int> partRange(const openvdb::CoordBBox& box, int a, int part, int parts) {
    const int firstLeaf = leafOf(box.min()[a]);
    const int leaves = leafCounts(box)[a];
    const int begin = (firstLeaf + int(std::int64_t(part) * leaves / parts)) * kLeafDim;
    const int end = (firstLeaf + int(std::int64_t(part + 1) * leaves / parts)) * kLeafDim - 1;
    return {std::max(begin, box.min()[a]), std::min(end, box.max()[a])};
}

}  // namespace

openvdb::Coord brickLattice(const openvdb::CoordBBox& box, std::size_t count) {
    const openvdb::Coord leaves = leafCounts(box);
    const openvdb::Vec3d sides = box.dim().asVec3d();
    openvdb::Coord best(0);
    double bestSurface = std::numeric_limits<double>::infinity();
    for (std::size_t x = 1; x <= count; ++x) {
        if (count % x != 0 || x > std::size_t(leaves.x())) continue;
        for (std::size_t y = 1; y <= count / x; ++y) {
            const std::size_t z = count / x / y;
            if ((count / x) % y != 0 || y > std::size_t(leaves.y()) || z > std::size_t(leaves.z())) continue;
            // Halo voxels per brick voxel go as the sum of 1 / side.
            const double surface = double(x) / sides.x() + double(y) / sides.y() + double(z) / sides.z();
            if (surface < bestSurface) {
                bestSurface = surface;
                best = openvdb::Coord(int(x), int(y), int(z));
            }
        }
    }
    if (best.x() == 0) {
        throw InputError("`bricks`", std::to_string(count) + " bricks of whole 8^3 leaves do not fit a volume of " +
                                         std::to_string(leaves.x()) + " x " + std::to_string(leaves.y()) + " x " +
                                         std::to_string(leaves.z()) + " leaves");
    }
    return best;
}

std::vector<Brick> planBricks(const VolumeTarget& target, const openvdb::Coord& lattice, int halo, std::size_t total) {
    const openvdb::CoordBBox& volume = target.box();
    std::vector<Brick> bricks;
    for (int k = 0; k < lattice.z(); ++k) {
        for (int j = 0; j < lattice.y(); ++j) {
            for (int i = 0; i < lattice.x(); ++i) {
                const int part[3] = {i, j, k};
                Brick brick;
                brick.index = bricks.size();
                brick.volume = volume;
                for (int a = 0; a < 3; ++a) {
                    const auto [first, last] = partRange(volume, a, part[a], lattice[a]);
                    brick.core.min()[a] = first;
                    brick.core.max()[a] = last;
                }
                brick.fitted = brick.core;
                brick.fitted.expand(halo);
                brick.fitted.intersect(volume);
                brick.halo = halo;
                brick.coreActiveVoxels = target.activeVoxelCount(brick.core);
                bricks.push_back(brick);
            }
        }
    }
    std::vector<std::uint64_t> content;
    for (const Brick& brick : bricks) content.push_back(brick.coreActiveVoxels);
    // No floor: a brick of background may get no Gaussian at all.
    const std::vector<std::size_t> budgets = splitBudget(total, content, 0);
    for (std::size_t b = 0; b < bricks.size(); ++b) bricks[b].budget = budgets[b];
    return bricks;
}

BrickSeams::BrickSeams(const std::vector<Brick>& bricks, int width) : mWidth(width) {
    for (const Brick& brick : bricks) {
        for (int a = 0; a < 3; ++a) {
            if (brick.core.min()[a] > brick.volume.min()[a]) mCuts[a].push_back(brick.core.min()[a]);
        }
    }
    for (std::vector<int>& cuts : mCuts) {
        std::sort(cuts.begin(), cuts.end());
        cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    }
}

bool BrickSeams::near(const openvdb::Coord& ijk) const {
    for (int a = 0; a < 3; ++a) {
        // A cut at c lies between voxels c - 1 and c: voxels c - width to c + width - 1 are near it.
        const auto after = std::upper_bound(mCuts[a].begin(), mCuts[a].end(), ijk[a] + mWidth);
        if (after != mCuts[a].begin() && *std::prev(after) > ijk[a] - mWidth) return true;
    }
    return false;
}

GaussianParameters fitBrick(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const Brick& brick,
                            const FitSettings& settings, const FitObserver& observer, FitReport* report) {
    const VolumeTarget target(grid, name, brick.fitted, brick.taper());
    if (brick.budget == 0) return GaussianParameters(0, target.channels());
    FitSettings one = settings;
    one.gaussians = brick.budget;
    // Adam needs as many steps in a brick as in the whole volume, so a brick draws its
    // share of each iteration's samples: iterations cost that share of the time, and
    // the bricks together draw what one whole-volume fit would.
    const double share = double(brick.fitted.volume()) / double(brick.volume.volume());
    const auto scaled = [share](std::size_t count, std::size_t least) {
        return std::max(least, std::size_t(std::llround(double(count) * share)));
    };
    one.voxelBatch = scaled(settings.batchFor(settings.gaussians), 1024);
    one.slicePixels = scaled(settings.slicePixels, 256);
    one.heldOutVoxels = scaled(settings.heldOutVoxels, 1024);
    one.meanRateSide = brick.volume.dim().asVec3d().length() / std::sqrt(3.0);
    one.seed = settings.seed + 1000003ull * std::uint64_t(brick.index + 1);
    return fitGaussians(target, one, observer, report);
}

}  // namespace gvr
