#include "pipeline/VolumeTarget.h"

#include "pipeline/Error.h"
#include "pipeline/FiniteValues.h"
#include "pipeline/Luminance.h"
#include "pipeline/Trilinear.h"
#include "pipeline/VolumeGrid.h"
#include "pipeline/VolumeMetadata.h"

#include <cfloat>
#include <cmath>
#include <sstream>
#include <type_traits>

namespace gvr {

namespace {

struct Range {
    double min = INFINITY, max = -INFINITY;
};

template <typename GridT>
Range luminanceRange(const GridT& grid) {
    Range range;
    for (auto value = grid.cbeginValueOn(); value; ++value) {
        double v;
        if constexpr (std::is_same_v<typename GridT::ValueType, openvdb::Vec3s>) {
            v = luminance(*value);
        } else {
            v = *value;
        }
        range.min = std::min(range.min, v);
        range.max = std::max(range.max, v);
    }
    return range;
}

/// Walks the active values of @a tree inside @a region, touching only the leaves
/// that overlap it: wholeLeaf(leaf) for a leaf inside the region, voxel(ijk) for
/// each active voxel of a leaf across its edge, then tile(box) for each active tile
/// above the leaves, clipped. Leaves come in tree order, voxels in leaf order.
template <typename TreeT, typename WholeLeaf, typename Voxel, typename Tile>
void walkActiveIn(const TreeT& tree, const openvdb::CoordBBox& region, const WholeLeaf& wholeLeaf, const Voxel& voxel,
                  const Tile& tile) {
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const openvdb::CoordBBox bounds = leaf->getNodeBoundingBox();
        if (!region.hasOverlap(bounds)) continue;
        if (region.isInside(bounds)) {
            wholeLeaf(*leaf);
            continue;
        }
        for (auto on = leaf->cbeginValueOn(); on; ++on) {
            if (region.isInside(on.getCoord())) voxel(on.getCoord());
        }
    }
    // Active tiles above the leaves: the value iterator, kept from descending to voxels.
    auto on = tree.cbeginValueOn();
    on.setMaxDepth(TreeT::ValueOnCIter::LEAF_DEPTH - 1);
    for (; on; ++on) {
        openvdb::CoordBBox bounds;
        on.getBoundingBox(bounds);
        bounds.intersect(region);
        if (!bounds.empty()) tile(bounds);
    }
}

template <typename TreeT>
std::uint64_t activeVoxelsIn(const TreeT& tree, const openvdb::CoordBBox& region) {
    std::uint64_t count = 0;
    walkActiveIn(
        tree, region, [&](const auto& leaf) { count += leaf.onVoxelCount(); }, [&](const openvdb::Coord&) { ++count; },
        [&](const openvdb::CoordBBox& tile) { count += tile.volume(); });
    return count;
}

/// The active flags of one leaf-sized block of @a tree.
template <typename TreeT>
std::bitset<kBlockVoxels> blockActiveOf(const TreeT& tree, const openvdb::Coord& origin) {
    std::bitset<kBlockVoxels> active;
    if (const auto* leaf = tree.probeConstLeaf(origin)) {
        for (auto on = leaf->getValueMask().beginOn(); on; ++on) active.set(on.pos());
    } else if (tree.isValueOn(origin)) {  // an active tile covers the whole block
        active.set();
    }
    return active;
}

/// Gaussians live in float index space, which steps by more than a voxel beyond
/// 2^24: a grid far out there would give empty boxes (an Embree assertion).
void requireFloatExactIndices(const openvdb::CoordBBox& box, const std::string& name) {
    constexpr std::int64_t kLimit = std::int64_t(1) << 24;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(std::int64_t(box.min()[a])) <= kLimit && std::abs(std::int64_t(box.max()[a])) <= kLimit) continue;
        std::ostringstream text;
        text << "its voxels reach index " << box.min() << " to " << box.max()
             << ", beyond +-2^24 where float positions step by more than a voxel; "
                "ingest it again to move its first voxel to index 0";
        throw InputError(name, text.str());
    }
}

}  // namespace

VolumeTarget::VolumeTarget(openvdb::GridBase::ConstPtr grid, const std::string& name,
                           const std::optional<openvdb::CoordBBox>& region, const std::optional<Taper>& taper)
    : mGrid(std::move(grid)), mTaper(taper) {
    mFloat = openvdb::GridBase::constGrid<openvdb::FloatGrid>(mGrid);
    mColour = openvdb::GridBase::constGrid<openvdb::Vec3SGrid>(mGrid);
    if (!isVolumeGrid(*mGrid)) throw InputError(name, notAVolumeGrid(*mGrid));
    mChannels = mFloat ? 1 : 3;
    const auto metadata = readVolumeMetadata(*mGrid);
    Range range;
    if (metadata) {
        mBox = openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(metadata->dims) - openvdb::Coord(1));
        range = {metadata->valueMin, metadata->valueMax};
    } else {
        mBox = mGrid->evalActiveVoxelBoundingBox();
        range = mFloat ? luminanceRange(*mFloat) : luminanceRange(*mColour);
    }
    if (region) mBox.intersect(*region);
    if (mBox.empty()) throw InputError(name, "grid '" + mGrid->getName() + "' has no voxels");
    requireFloatExactIndices(mBox, name);
    // A region's voxels may have been read on demand, never checked as a whole grid.
    if (region) requireFiniteValues(*mGrid, name, mBox);
    const openvdb::Vec3d background =
        mFloat ? openvdb::Vec3d(mFloat->background()) : openvdb::Vec3d(mColour->background());
    // Grey: background to the top of the range spans 0..1. RGB: the luminance range
    // does, so all three channels share one scale.
    const double top = mFloat ? range.max - background[0] : range.max - range.min;
    // An asset keeps its mapping in float range: a wider span (values at float's
    // limits, +-3.4e38) would be written and then refused by every reader.
    const bool finiteRange = std::isfinite(range.min) && std::isfinite(range.max);
    if (finiteRange && (std::abs(top) > double(FLT_MAX) || range.max - range.min > double(FLT_MAX))) {
        std::ostringstream span;
        span << range.min << " to " << range.max;
        throw InputError(
            name, "values span " + span.str() + ", wider than float32 can hold (3.4e38); rescale the volume to fit it");
    }
    mMapping.scale = top > 0.0 && std::isfinite(top) ? top : 1.0;
    for (int c = 0; c < 3; ++c) mMapping.offset[c] = mChannels == 1 ? background[0] : background[c];
    mPeak =
        std::isfinite(range.max - range.min) && range.max > range.min ? (range.max - range.min) / mMapping.scale : 1.0;
    mActiveVoxels = region ? activeVoxelCount(mBox) : mGrid->activeVoxelCount();
}

std::uint64_t VolumeTarget::activeVoxelCount(const openvdb::CoordBBox& region) const {
    return mFloat ? activeVoxelsIn(mFloat->tree(), region) : activeVoxelsIn(mColour->tree(), region);
}

template <typename TreeOrAccessor>
void VolumeTarget::normalisedValue(const TreeOrAccessor& source, const openvdb::Coord& ijk, float* out) const {
    if constexpr (std::is_same_v<typename TreeOrAccessor::ValueType, float>) {
        out[0] = float(mMapping.toNormalised(source.getValue(ijk), 0));
    } else {
        const openvdb::Vec3s v = source.getValue(ijk);
        for (int c = 0; c < 3; ++c) out[c] = float(mMapping.toNormalised(v[c], c));
    }
    if (mTaper) applyTaper(ijk, out);
}

void VolumeTarget::valueAt(const openvdb::Coord& ijk, float* out) const {
    if (mFloat) {
        normalisedValue(mFloat->tree(), ijk, out);
    } else {
        normalisedValue(mColour->tree(), ijk, out);
    }
}

namespace {

/// The values of one leaf-sized block of @a tree, in physical units, through @a put(offset, value).
template <typename TreeT, typename Put>
void forEachBlockValue(const TreeT& tree, const openvdb::Coord& origin, const Put& put) {
    using LeafT = typename TreeT::LeafNodeType;
    if (const LeafT* leaf = tree.probeConstLeaf(origin)) {
        for (openvdb::Index offset = 0; offset < LeafT::SIZE; ++offset) put(int(offset), leaf->getValue(offset));
        return;
    }
    const auto value = tree.getValue(origin);  // a tile or the background: one value for the block
    for (openvdb::Index offset = 0; offset < LeafT::SIZE; ++offset) put(int(offset), value);
}

}  // namespace

void VolumeTarget::blockValues(const openvdb::Coord& origin, float* out) const {
    if (mFloat) {
        forEachBlockValue(mFloat->tree(), origin,
                          [&](int offset, float v) { out[offset] = float(mMapping.toNormalised(v, 0)); });
    } else {
        forEachBlockValue(mColour->tree(), origin, [&](int offset, const openvdb::Vec3s& v) {
            for (int c = 0; c < 3; ++c) out[3 * offset + c] = float(mMapping.toNormalised(v[c], c));
        });
    }
    if (!mTaper) return;
    for (int offset = 0; offset < kBlockVoxels; ++offset) {
        const openvdb::Coord ijk = blockVoxel(origin, offset);
        applyTaper(ijk, out + offset * mChannels);
    }
}

void VolumeTarget::applyTaper(const openvdb::Coord& ijk, float* out) const {
    const float weight = mTaper->at(ijk);
    for (int c = 0; c < mChannels; ++c) out[c] *= weight;
}

std::bitset<kBlockVoxels> VolumeTarget::blockActive(const openvdb::Coord& origin) const {
    return mFloat ? blockActiveOf(mFloat->tree(), origin) : blockActiveOf(mColour->tree(), origin);
}

bool VolumeTarget::isActive(const openvdb::Coord& ijk) const {
    return mFloat ? mFloat->tree().isValueOn(ijk) : mColour->tree().isValueOn(ijk);
}

void VolumeTarget::trilinearAt(const float x[3], float* out) const {
    double sum[3] = {0, 0, 0};
    forEachTrilinearCorner(openvdb::Vec3d(x[0], x[1], x[2]), [&](const openvdb::Coord& corner, double weight) {
        float value[3];
        valueAt(corner, value);
        for (int c = 0; c < mChannels; ++c) sum[c] += weight * value[c];
    });
    for (int c = 0; c < mChannels; ++c) out[c] = float(sum[c]);
}

void VolumeTarget::forEachActiveVoxel(const std::function<void(const openvdb::Coord&)>& visit) const {
    const auto visitTree = [&](const auto& tree) {
        walkActiveIn(
            tree, mBox,
            [&](const auto& leaf) {
                for (auto on = leaf.cbeginValueOn(); on; ++on) visit(on.getCoord());
            },
            visit,
            [&](const openvdb::CoordBBox& tile) {
                for (auto ijk = tile.begin(); ijk; ++ijk) visit(*ijk);
            });
    };
    if (mFloat)
        visitTree(mFloat->tree());
    else
        visitTree(mColour->tree());
}

namespace {

/// |central differences| at @a ijk of @a scalar(Coord), the one gradient that
/// gradientMagnitude() and blockGradientMagnitudes() both give.
template <typename Scalar>
float centralGradientMagnitude(const openvdb::Coord& ijk, const Scalar& scalar) {
    float squared = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
        openvdb::Coord step(0);
        step[axis] = 1;
        const float derivative = 0.5f * (scalar(ijk + step) - scalar(ijk - step));
        squared += derivative * derivative;
    }
    return std::sqrt(squared);
}

}  // namespace

float VolumeTarget::gradientMagnitude(const openvdb::Coord& ijk) const {
    return centralGradientMagnitude(ijk, [&](const openvdb::Coord& at) {
        float v[3];
        valueAt(at, v);
        return mChannels == 1 ? v[0] : float(luminance(v));
    });
}

void VolumeTarget::blockGradientMagnitudes(const openvdb::Coord& origin, float* out) const {
    float values[kBlockVoxels * 3];
    blockValues(origin, values);
    const openvdb::CoordBBox block(origin, origin.offsetBy(kBlockDim - 1));
    const auto gradients = [&](const auto& accessor) {
        const auto scalarOf = [&](const float* v) { return mChannels == 1 ? v[0] : float(luminance(v)); };
        const auto scalar = [&](const openvdb::Coord& at) {
            if (block.isInside(at)) return scalarOf(values + blockOffset(at - origin) * mChannels);
            float v[3];
            normalisedValue(accessor, at, v);
            return scalarOf(v);
        };
        for (int offset = 0; offset < kBlockVoxels; ++offset) {
            out[offset] = centralGradientMagnitude(blockVoxel(origin, offset), scalar);
        }
    };
    if (mFloat) {
        gradients(mFloat->getConstAccessor());
    } else {
        gradients(mColour->getConstAccessor());
    }
}

}  // namespace gvr
