#include "FieldToGrid.h"

#include "Error.h"
#include "LeafAssembly.h"
#include "Luminance.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace gvr {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::Vec3d;
using openvdb::math::Mat4d;

namespace {

/// A lattice this large would need more than 128 MiB just to mark occupied leaves.
constexpr double kMaxLatticeVoxels = 68719476736.0;  // 2^36

double axisLength(const Mat4d& worldFromIndex, int axis) {
    return Vec3d(worldFromIndex(axis, 0), worldFromIndex(axis, 1), worldFromIndex(axis, 2)).length();
}

int toIndex(double v) { return int(std::clamp(v, -1073741824.0, 1073741824.0)); }

/// The lattice voxels whose centres may lie inside the field-space box [lower, upper].
CoordBBox latticeVoxelsIn(const float lower[3], const float upper[3], const Mat4d& latticeFromField) {
    Vec3d lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3d p = latticeFromField.transform(Vec3d(corner & 1 ? upper[0] : lower[0],
                                                         corner & 2 ? upper[1] : lower[1],
                                                         corner & 4 ? upper[2] : lower[2]));
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
        const Coord c(corner & 1 ? voxels.max().x() : voxels.min().x(), corner & 2 ? voxels.max().y() : voxels.min().y(),
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

/// Origins of the leaves that at least one Gaussian reaches.
std::vector<Coord> occupiedLeaves(const std::vector<CoordBBox>& reach, const CoordBBox& latticeBox, int leafDim) {
    const int shift = int(std::log2(leafDim));
    const Coord first(latticeBox.min().x() >> shift, latticeBox.min().y() >> shift, latticeBox.min().z() >> shift);
    const Coord last(latticeBox.max().x() >> shift, latticeBox.max().y() >> shift, latticeBox.max().z() >> shift);
    const Coord blocks = last - first + Coord(1);
    std::vector<std::uint8_t> occupied(std::size_t(blocks.x()) * blocks.y() * blocks.z(), 0);
    for (const CoordBBox& box : reach) {
        if (box.empty()) continue;
        for (int z = (box.min().z() >> shift); z <= (box.max().z() >> shift); ++z) {
            for (int y = (box.min().y() >> shift); y <= (box.max().y() >> shift); ++y) {
                for (int x = (box.min().x() >> shift); x <= (box.max().x() >> shift); ++x) {
                    const Coord b = Coord(x, y, z) - first;
                    occupied[(std::size_t(b.z()) * blocks.y() + b.y()) * blocks.x() + b.x()] = 1;
                }
            }
        }
    }
    std::vector<Coord> origins;
    for (int z = 0; z < blocks.z(); ++z) {
        for (int y = 0; y < blocks.y(); ++y) {
            for (int x = 0; x < blocks.x(); ++x) {
                if (occupied[(std::size_t(z) * blocks.y() + y) * blocks.x() + x]) {
                    origins.emplace_back((first.x() + x) << shift, (first.y() + y) << shift, (first.z() + z) << shift);
                }
            }
        }
    }
    return origins;
}

template <typename GridT>
class LeafSampler {
public:
    using LeafT = typename GridT::TreeType::LeafNodeType;
    using ValueT = typename GridT::ValueType;
    static constexpr int kVoxels = LeafT::SIZE;

    LeafSampler(const GaussianField& field, const Mat4d& fieldFromLattice, const CoordBBox& latticeBox,
                const std::vector<CoordBBox>& reach, const FieldToGridSettings& settings)
        : mField(field), mFieldFromLattice(fieldFromLattice), mLatticeBox(latticeBox), mReach(reach),
          mSettings(settings), mChannels(field.channels()) {}

    std::unique_ptr<LeafT> operator()(const Coord& origin) const {
        CoordBBox voxels(origin, origin + Coord(LeafT::DIM - 1));
        voxels.intersect(mLatticeBox);
        if (voxels.empty()) return nullptr;
        float points[kVoxels][3];
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            const Vec3d p = mFieldFromLattice.transform((*ijk).asVec3d());
            float* point = points[LeafT::coordToOffset(*ijk)];
            for (int a = 0; a < 3; ++a) point[a] = float(p[a]);
        }
        float sums[kVoxels * 3] = {};
        addGaussians(voxels, points, sums);
        return leafFrom(origin, voxels, sums);
    }

    /// What inactive voxels hold: the physical value of normalised 0.
    ValueT background() const {
        float physical[3];
        for (int c = 0; c < mChannels; ++c) physical[c] = float(mSettings.mapping.toPhysical(0.0, c));
        return valueOf(physical);
    }

private:
    /// Adds each reaching Gaussian in index order: the order GaussianField::evaluate
    /// sums in, so both give the same float at the same point.
    void addGaussians(const CoordBBox& voxels, const float (*points)[3], float* sums) const {
        float lower[3], upper[3];
        fieldBoundsOf(voxels, mFieldFromLattice, lower, upper);
        std::vector<std::uint32_t> hits;
        mField.bvh().overlapping(lower, upper, hits);
        std::sort(hits.begin(), hits.end());
        for (std::uint32_t index : hits) {
            CoordBBox reached = mReach[index];
            reached.intersect(voxels);
            if (reached.empty()) continue;
            const ActiveGaussian& g = mField.gaussians()[index];
            for (auto ijk = reached.begin(); ijk; ++ijk) {
                const auto offset = LeafT::coordToOffset(*ijk);
                accumulateValue(g, points[offset], mField.cutoff2(), mChannels, sums + offset * mChannels);
            }
        }
    }

    std::unique_ptr<LeafT> leafFrom(const Coord& origin, const CoordBBox& voxels, const float* sums) const {
        auto leaf = std::make_unique<LeafT>(origin, background(), false);
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            const auto offset = LeafT::coordToOffset(*ijk);
            const float* sum = sums + offset * mChannels;
            if (std::all_of(sum, sum + mChannels, [](float v) { return v == 0.0f; })) continue;  // unreached
            float physical[3];
            for (int c = 0; c < mChannels; ++c) physical[c] = float(mSettings.mapping.toPhysical(sum[c], c));
            const double key = mChannels == 1 ? physical[0] : luminance(physical);
            if (mSettings.threshold && key <= *mSettings.threshold) continue;
            leaf->setValueOn(offset, valueOf(physical));
        }
        return leaf->isEmpty() ? nullptr : std::move(leaf);
    }

    static ValueT valueOf(const float* physical) {
        if constexpr (std::is_same_v<ValueT, openvdb::Vec3s>) return ValueT(physical[0], physical[1], physical[2]);
        else return physical[0];
    }

    const GaussianField& mField;
    const Mat4d mFieldFromLattice;
    const CoordBBox mLatticeBox;
    const std::vector<CoordBBox>& mReach;
    const FieldToGridSettings& mSettings;
    const int mChannels;
};

template <typename GridT>
typename GridT::Ptr sampleInto(const GaussianField& field, const Mat4d& fieldWorldFromIndex, const Lattice& lattice,
                               const FieldToGridSettings& settings, const ProgressFn& progress) {
    const Mat4d latticeFromField = fieldWorldFromIndex * lattice.worldFromIndex.inverse();
    const Mat4d fieldFromLattice = lattice.worldFromIndex * fieldWorldFromIndex.inverse();
    const std::vector<CoordBBox> reach = latticeReach(field, latticeFromField, lattice.box);
    const LeafSampler<GridT> sampler(field, fieldFromLattice, lattice.box, reach, settings);
    const auto origins = occupiedLeaves(reach, lattice.box, GridT::TreeType::LeafNodeType::DIM);
    typename GridT::Ptr grid = assembleGrid<GridT>(origins, sampler.background(), sampler, progress);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(lattice.worldFromIndex));
    return grid;
}

}  // namespace

Lattice sourceLattice(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims) {
    return {worldFromIndex, CoordBBox(Coord(0), Coord(dims) - Coord(1))};
}

Lattice resizedLattice(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims, double voxelSizeMm) {
    if (!(voxelSizeMm > 0.0) || !std::isfinite(voxelSizeMm)) {
        throw InputError("--voxel-size", "must be a positive number of mm");
    }
    Mat4d sourceFromResized = Mat4d::identity();
    Coord size;
    double total = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
        // One new voxel spans `step` source voxels; the cells start at the source's corner, -0.5.
        const double step = voxelSizeMm / axisLength(worldFromIndex, axis);
        const double count = std::max(1.0, std::ceil(dims[axis] / step - 1e-9));
        total *= count;
        if (count > 2147483647.0 || total > kMaxLatticeVoxels) {
            throw InputError("--voxel-size", std::to_string(voxelSizeMm) + " mm would need more than 2^36 voxels");
        }
        size[axis] = int(count);
        sourceFromResized(axis, axis) = step;
        sourceFromResized(3, axis) = 0.5 * step - 0.5;
    }
    return {sourceFromResized * worldFromIndex, CoordBBox(Coord(0), size - Coord(1))};
}

double voxelSizeForResolution(const Mat4d& worldFromIndex, const openvdb::Vec3i& dims, int samples) {
    if (samples < 1) throw InputError("--resolution", "must be at least 1 voxel");
    double longest = 0.0;
    for (int axis = 0; axis < 3; ++axis) longest = std::max(longest, dims[axis] * axisLength(worldFromIndex, axis));
    return longest / samples;
}

openvdb::GridBase::Ptr fieldToGrid(const GaussianField& field, const Mat4d& fieldWorldFromIndex, const Lattice& lattice,
                                   const FieldToGridSettings& settings, const ProgressFn& progress) {
    openvdb::GridBase::Ptr grid;
    if (field.channels() == 1) {
        grid = sampleInto<openvdb::FloatGrid>(field, fieldWorldFromIndex, lattice, settings, progress);
        grid->setName("density");
    } else {
        grid = sampleInto<openvdb::Vec3SGrid>(field, fieldWorldFromIndex, lattice, settings, progress);
        grid->setName("color");
    }
    return grid;
}

}  // namespace gvr
