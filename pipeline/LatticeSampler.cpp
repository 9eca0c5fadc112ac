#include "pipeline/LatticeSampler.h"

#include "pipeline/BlockKernel.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace gvr {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::Vec3d;
using openvdb::math::Mat4d;

namespace {

/// A lattice this large would need more than 128 MiB just to mark occupied leaves.
constexpr double kMaxLatticeVoxels = 68719476736.0;  // 2^36

int toIndex(double v) { return int(std::clamp(v, -1073741824.0, 1073741824.0)); }

/// The lattice voxels whose centres may lie inside the field-space box [lower, upper].
CoordBBox latticeVoxelsIn(const float lower[3], const float upper[3], const Mat4d& latticeFromField) {
    Vec3d lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3d p = latticeFromField.transform(Vec3d(
            corner & 1 ? upper[0] : lower[0], corner & 2 ? upper[1] : lower[1], corner & 4 ? upper[2] : lower[2]));
        lo = openvdb::math::minComponent(lo, p);
        hi = openvdb::math::maxComponent(hi, p);
    }
    return CoordBBox(Coord(toIndex(std::ceil(lo[0])), toIndex(std::ceil(lo[1])), toIndex(std::ceil(lo[2]))),
                     Coord(toIndex(std::floor(hi[0])), toIndex(std::floor(hi[1])), toIndex(std::floor(hi[2]))));
}

/// Field-space bounds of a box of lattice voxel centres, widened by a float ulp's worth.
void fieldBoundsOf(const CoordBBox& voxels, const Mat4d& fieldFromLattice, float lower[3], float upper[3]) {
    Vec3d lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const Coord c(corner & 1 ? voxels.max().x() : voxels.min().x(),
                      corner & 2 ? voxels.max().y() : voxels.min().y(),
                      corner & 4 ? voxels.max().z() : voxels.min().z());
        const Vec3d p = fieldFromLattice.transform(c.asVec3d());
        lo = openvdb::math::minComponent(lo, p);
        hi = openvdb::math::maxComponent(hi, p);
    }
    for (int a = 0; a < 3; ++a) {
        const double pad = 1e-5 * (1.0 + std::max(std::abs(lo[a]), std::abs(hi[a])));
        lower[a] = float(lo[a] - pad);
        upper[a] = float(hi[a] + pad);
    }
}

/// What each Gaussian can reach, as a box of lattice voxels.
std::vector<CoordBBox> latticeReach(const GaussianField& field, const Mat4d& latticeFromField,
                                    const CoordBBox& latticeBox) {
    const std::vector<Box>& boxes = field.bvh().boxes();
    std::vector<CoordBBox> reach(boxes.size());
    tbb::parallel_for(std::size_t(0), boxes.size(), [&](std::size_t g) {
        reach[g] = latticeVoxelsIn(boxes[g].lower.data(), boxes[g].upper.data(), latticeFromField);
        reach[g].intersect(latticeBox);
    });
    return reach;
}

}  // namespace

BlockLists::BlockLists(const std::vector<CoordBBox>& reach, const BlockSlots& slots) : mStarts(slots.size() + 1, 0) {
    // Counted, then filled in index order, so that each list is ascending.
    for (const CoordBBox& box : reach) {
        if (!box.empty()) slots.forEachSlotOver(box, [&](std::size_t slot) { ++mStarts[slot + 1]; });
    }
    for (std::size_t slot = 0; slot < slots.size(); ++slot) mStarts[slot + 1] += mStarts[slot];
    mGaussians.resize(mStarts.back());
    std::vector<std::size_t> next(mStarts.begin(), mStarts.end() - 1);
    for (std::size_t g = 0; g < reach.size(); ++g) {
        if (!reach[g].empty()) {
            slots.forEachSlotOver(reach[g], [&](std::size_t slot) { mGaussians[next[slot]++] = std::uint32_t(g); });
        }
    }
}

Lattice sourceLattice(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims) {
    return {worldFromIndex, CoordBBox(Coord(0), Coord(dims) - Coord(1))};
}

Lattice resizedLattice(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims, double voxelSizeMm) {
    if (!(voxelSizeMm > 0.0) || !std::isfinite(voxelSizeMm)) {
        throw InputError("`voxel_size`", "must be a positive number of mm");
    }
    // Larger, the volume is one voxel all the same; far larger (1e300 mm), the
    // transform's determinant overflows and no reader takes the file.
    const double longest = voxelSizeForResolution(worldFromIndex, dims, 1);
    if (voxelSizeMm > longest) {
        std::ostringstream message;
        message << voxelSizeMm << " mm is larger than the volume's longest extent, " << longest << " mm";
        throw InputError("`voxel_size`", message.str());
    }
    Mat4d sourceFromResized = Mat4d::identity();
    Coord size;
    double total = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
        // One new voxel spans `step` source voxels; the cells start at the source's corner, -0.5.
        const double step = voxelSizeMm / axisSpacing(worldFromIndex)[axis];
        const double count = std::max(1.0, std::ceil(dims[axis] / step - 1e-9));
        total *= count;
        if (count > 2147483647.0 || total > kMaxLatticeVoxels) {
            throw InputError("`voxel_size`", std::to_string(voxelSizeMm) + " mm would need more than 2^36 voxels");
        }
        size[axis] = int(count);
        sourceFromResized(axis, axis) = step;
        sourceFromResized(3, axis) = 0.5 * step - 0.5;
    }
    return {sourceFromResized * worldFromIndex, CoordBBox(Coord(0), size - Coord(1))};
}

double voxelSizeForResolution(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims, int samples) {
    if (samples < 1) throw InputError("`resolution`", "must be at least 1 voxel");
    double longest = 0.0;
    for (int axis = 0; axis < 3; ++axis) longest = std::max(longest, dims[axis] * axisSpacing(worldFromIndex)[axis]);
    return longest / samples;
}

LatticeSampler::LatticeSampler(const GaussianField& field, const Mat4d& fieldWorldFromIndex, const Lattice& lattice,
                               const CoordBBox& fieldBox)
    : mField(field),
      mLattice(lattice),
      mFieldFromLattice(lattice.worldFromIndex * fieldWorldFromIndex.inverse()),
      mFieldCells(fieldBox.min().asVec3d() - Vec3d(0.5), fieldBox.max().asVec3d() + Vec3d(0.5)),
      mReach(latticeReach(field, fieldWorldFromIndex * lattice.worldFromIndex.inverse(), lattice.box)),
      mSlots(lattice.box),
      mLists(mReach, mSlots) {
    for (int a = 0; a < 3; ++a) mLatticeSteps[a] = mFieldFromLattice.transform3x3(Vec3d(a == 0, a == 1, a == 2));
}

float LatticeSampler::reachCeiling(const std::uint32_t* hits, const std::uint32_t* hitsEnd, const float lower[3],
                                   const float upper[3], int channels) const {
    // Over the block a Gaussian is at most its peak times exp(-d^2 / (2 sigma_max^2)),
    // d the distance from its mean to the block: q >= |x - mean|^2 / sigma_max^2.
    float ceiling = 0.0f;
    for (const std::uint32_t* hit = hits; hit != hitsEnd; ++hit) {
        const ActiveGaussian& g = mField.gaussians()[*hit];
        float d2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float gap = std::max({lower[a] - g.mean[a], 0.0f, g.mean[a] - upper[a]});
            d2 += gap * gap;
        }
        const float widest = 1.0f / std::sqrt(std::min({g.invVariance[0], g.invVariance[1], g.invVariance[2]}));
        float peak = 0.0f;
        for (int c = 0; c < channels; ++c) peak = std::max(peak, std::abs(g.amplitude[c]));
        ceiling += peak * std::exp(-0.5f * d2 / (widest * widest));
    }
    return ceiling;
}

std::size_t LatticeSampler::reachingGaussians() const {
    return std::size_t(std::count_if(mReach.begin(), mReach.end(), [](const CoordBBox& box) { return !box.empty(); }));
}

bool allVoxelsInside(const CoordBBox& voxels, const Mat4d& cellsFromVoxels, const openvdb::BBoxd& cells) {
    // The box is convex, so its corners tell.
    for (int corner = 0; corner < 8; ++corner) {
        const Coord c(corner & 1 ? voxels.max().x() : voxels.min().x(),
                      corner & 2 ? voxels.max().y() : voxels.min().y(),
                      corner & 4 ? voxels.max().z() : voxels.min().z());
        if (!cells.isInside(cellsFromVoxels.transform(c.asVec3d()))) return false;
    }
    return true;
}

std::vector<Coord> LatticeSampler::occupiedBlocks() const {
    std::vector<Coord> occupied;
    for (std::size_t slot = 0; slot < mSlots.size(); ++slot) {
        if (mLists.count(slot) > 0) occupied.push_back(mSlots.originOf(slot));
    }
    return occupied;
}

namespace {

/// Adds amplitude x exp(-q/2) over the rows (along z) of @a reached, where q is
/// within the cutoff and the sample lies in the volume's cells, kBlockDim samples
/// a row in lanes of Floats: Floats4, or Floats8 in code compiled for AVX2.
template <typename Floats>
__attribute__((always_inline)) inline void addRowTerms(const BlockQuadratic& quad, const Coord& origin,
                                                       const CoordBBox& reached, const std::int32_t inCells[],
                                                       float cutoff2, const float amplitude[3], int channels,
                                                       float* sums) {
    using Ints = decltype(Floats{} < Floats{});
    constexpr int kLanes = sizeof(Floats) / sizeof(float);
    const Coord first = reached.min() - origin, last = reached.max() - origin;
    const auto firstY = [&](int) { return first.y(); };
    forEachRowCrossed(quad, first.x(), last.x(), firstY, last.y(), 1, cutoff2,
                      [&](int x, int y, const RowParabola& row) {
                          const int base = (x * kBlockDim + y) * kBlockDim;
                          float* sumsOfRow = sums + base * channels;
                          for (int part = 0; part < kBlockDim; part += kLanes) {
                              const Floats q = rowQ<Floats>(row, part);
                              Ints keep;
                              std::memcpy(&keep, inCells + base + part, sizeof keep);
                              keep &= q <= cutoff2;
                              int kept = 0;
                              for (int i = 0; i < kLanes; ++i) kept |= keep[i];
                              if (!kept) continue;
                              const Floats term = kernelWhere(q, keep);
                              if (channels == 1) {
                                  Floats sum;
                                  std::memcpy(&sum, sumsOfRow + part, sizeof sum);
                                  sum += amplitude[0] * term;
                                  std::memcpy(sumsOfRow + part, &sum, sizeof sum);
                                  continue;
                              }
                              for (int i = 0; i < kLanes; ++i) {
                                  for (int c = 0; c < channels; ++c)
                                      sumsOfRow[(part + i) * channels + c] += amplitude[c] * term[i];
                              }
                          }
                      });
}

/// The same, eight samples at once where the processor has AVX2 (the stack
/// build's hot loop); the arithmetic is lane for lane that of addRowTerms<Floats4>.
__attribute__((target("avx2"))) void addRowTermsAvx2(const BlockQuadratic& quad, const Coord& origin,
                                                     const CoordBBox& reached, const std::int32_t inCells[],
                                                     float cutoff2, const float amplitude[3], int channels,
                                                     float* sums) {
    addRowTerms<Floats8>(quad, origin, reached, inCells, cutoff2, amplitude, channels, sums);
}

}  // namespace

CoordBBox LatticeSampler::sampleBlock(const Coord& origin, float* sums, float skipUpTo,
                                      BlockEvaluation evaluation) const {
    CoordBBox voxels(origin, origin + Coord(kBlockDim - 1));
    voxels.intersect(mLattice.box);
    if (voxels.empty()) return voxels;
    // -1 where a lattice voxel lies inside the field's cells, 0 elsewhere (beyond
    // the lattice too, as rows cover whole blocks).
    alignas(16) std::int32_t inCells[kBlockVoxels] = {};
    float points[kBlockVoxels][3];
    const bool exact = evaluation == BlockEvaluation::Exact;
    const bool eightLanes = evaluation == BlockEvaluation::Rows && processorHasAvx2();
    // Rows need only the mask; exact evaluation also needs each point.
    const bool allInCells = !exact && allVoxelsInside(voxels, mFieldFromLattice, mFieldCells);
    for (auto ijk = voxels.begin(); ijk; ++ijk) {
        const int offset = blockOffset(*ijk);
        if (allInCells) {
            inCells[offset] = -1;
            continue;
        }
        const Vec3d p = mFieldFromLattice.transform((*ijk).asVec3d());
        inCells[offset] = mFieldCells.isInside(p) ? -1 : 0;
        if (exact) {
            for (int a = 0; a < 3; ++a) points[offset][a] = float(p[a]);
        }
    }
    // Each reaching Gaussian in index order: the order GaussianField::evaluate sums
    // in, so that exact evaluation gives the same float at the same point.
    const std::size_t slot = mSlots.slotOf(mSlots.blockOf(origin));
    const std::uint32_t *hits = mLists.begin(slot), *hitsEnd = mLists.end(slot);
    const int channels = mField.channels();
    if (skipUpTo >= 0.0f) {
        float lower[3], upper[3];
        fieldBoundsOf(voxels, mFieldFromLattice, lower, upper);
        if (reachCeiling(hits, hitsEnd, lower, upper, channels) <= skipUpTo) return CoordBBox();
    }
    for (const std::uint32_t* hit = hits; hit != hitsEnd; ++hit) {
        const std::uint32_t index = *hit;
        CoordBBox reached = mReach[index];
        reached.intersect(voxels);
        if (reached.empty()) continue;
        if (!exact) {
            addRows(index, origin, reached, inCells, sums, eightLanes);
            continue;
        }
        const ActiveGaussian& g = mField.gaussians()[index];
        for (auto ijk = reached.begin(); ijk; ++ijk) {
            const int offset = blockOffset(*ijk);
            if (!inCells[offset]) continue;
            accumulateValue(g, points[offset], mField.cutoff2(), channels, sums + offset * channels);
        }
    }
    return voxels;
}

void LatticeSampler::addRows(std::uint32_t index, const Coord& origin, const CoordBBox& reached,
                             const std::int32_t inCells[], float* sums, bool eightLanes) const {
    // In the Gaussian's frame, u = R^T (p - mean) and q = sum_c u_c^2 / sigma_c^2. With
    // r the lattice position relative to the block's origin, u = u0 + sum_a r_a w_a,
    // so q = h + 2 g.r + r^T G r: a quadratic in r, and in z along each row.
    const ActiveGaussian& g = mField.gaussians()[index];
    const auto toFrame = [&g](const Vec3d& d, double u[3]) {
        for (int c = 0; c < 3; ++c) u[c] = g.rotation[c] * d[0] + g.rotation[3 + c] * d[1] + g.rotation[6 + c] * d[2];
    };
    double u0[3], w[3][3];
    toFrame(mFieldFromLattice.transform(origin.asVec3d()) - Vec3d(g.mean[0], g.mean[1], g.mean[2]), u0);
    for (int a = 0; a < 3; ++a) toFrame(mLatticeSteps[a], w[a]);
    BlockQuadratic quad{};
    for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) quad.gLin[a] += g.invVariance[c] * w[a][c] * u0[c];
        for (int b = 0; b < 3; ++b) {
            for (int c = 0; c < 3; ++c) quad.G[a][b] += g.invVariance[c] * w[a][c] * w[b][c];
        }
    }
    for (int c = 0; c < 3; ++c) quad.h += g.invVariance[c] * u0[c] * u0[c];
    const int channels = mField.channels();
    // A copy: stores to the sums could otherwise alias the Gaussian's amplitudes.
    float amplitude[3];
    std::copy(g.amplitude, g.amplitude + channels, amplitude);
    if (eightLanes) {
        addRowTermsAvx2(quad, origin, reached, inCells, mField.cutoff2(), amplitude, channels, sums);
    } else {
        addRowTerms<Floats4>(quad, origin, reached, inCells, mField.cutoff2(), amplitude, channels, sums);
    }
}

}  // namespace gvr
