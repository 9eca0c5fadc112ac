#include "pipeline/ThresholdHoles.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gvr {

namespace {

struct SliceCounts {
    std::uint64_t enclosedInactive = 0, inside = 0;
};

/// Marks the inactive pixels of one slice that reach the slice's border through
/// inactive pixels; the others are enclosed.
SliceCounts countSlice(const std::vector<std::uint8_t>& active, int width, int height) {
    std::vector<std::uint8_t> outside(active.size(), 0);
    std::vector<int> stack;
    const auto push = [&](int x, int y) {
        const int at = y * width + x;
        if (active[at] || outside[at]) return;
        outside[at] = 1;
        stack.push_back(at);
    };
    for (int x = 0; x < width; ++x) {
        push(x, 0);
        push(x, height - 1);
    }
    for (int y = 0; y < height; ++y) {
        push(0, y);
        push(width - 1, y);
    }
    while (!stack.empty()) {
        const int at = stack.back();
        stack.pop_back();
        const int x = at % width, y = at / width;
        if (x > 0) push(x - 1, y);
        if (x + 1 < width) push(x + 1, y);
        if (y > 0) push(x, y - 1);
        if (y + 1 < height) push(x, y + 1);
    }
    SliceCounts counts;
    for (std::size_t at = 0; at < active.size(); ++at) {
        if (outside[at]) continue;
        ++counts.inside;
        if (!active[at]) ++counts.enclosedInactive;
    }
    return counts;
}

}  // namespace

double enclosedInactiveShare(const openvdb::GridBase& grid) {
    const openvdb::CoordBBox box = grid.evalActiveVoxelBoundingBox();
    if (box.empty()) return 0.0;
    openvdb::MaskGrid mask;
    grid.apply<openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid, openvdb::Vec3SGrid, openvdb::Int32Grid>>(
        [&](const auto& typed) { mask.topologyUnion(typed); });
    // Slabs of 8 slices, one at a time, so that a streamed ingest of a volume larger
    // than memory needs flags for 8 slices only: leaves and active tiles by slab first.
    using LeafT = openvdb::MaskTree::LeafNodeType;
    const int firstZ = (box.min().z() >> 3) << 3;  // leaf-aligned
    const std::size_t slabCount = std::size_t((box.max().z() - firstZ) / 8 + 1);
    std::vector<std::vector<const LeafT*>> leavesBySlab(slabCount);
    for (auto leaf = mask.tree().cbeginLeaf(); leaf; ++leaf) {
        leavesBySlab[std::size_t((leaf->origin().z() - firstZ) / 8)].push_back(leaf.getLeaf());
    }
    std::vector<openvdb::CoordBBox> tiles;
    auto tile = mask.tree().cbeginValueOn();
    tile.setMaxDepth(openvdb::MaskTree::ValueOnCIter::LEAF_DEPTH - 1);  // tiles only, not voxels
    for (; tile; ++tile) tiles.push_back(tile.getBoundingBox());

    const openvdb::Coord size = box.dim();
    const std::size_t sliceSize = std::size_t(size.x()) * size.y();
    SliceCounts total;
    std::vector<std::uint8_t> active(sliceSize * 8);
    for (std::size_t slab = 0; slab < slabCount; ++slab) {
        openvdb::CoordBBox slabBox(openvdb::Coord(box.min().x(), box.min().y(), firstZ + 8 * int(slab)),
                                   openvdb::Coord(box.max().x(), box.max().y(), firstZ + 8 * int(slab) + 7));
        slabBox.intersect(box);
        std::fill(active.begin(), active.end(), 0);
        const auto set = [&](const openvdb::Coord& ijk) {
            const openvdb::Coord at = ijk - slabBox.min();
            active[(std::size_t(at.z()) * size.y() + at.y()) * size.x() + at.x()] = 1;
        };
        for (const LeafT* leaf : leavesBySlab[slab]) {
            for (auto on = leaf->cbeginValueOn(); on; ++on) set(on.getCoord());
        }
        for (openvdb::CoordBBox part : tiles) {
            part.intersect(slabBox);
            for (auto ijk = part.begin(); ijk; ++ijk) set(*ijk);
        }
        for (int z = 0; z < slabBox.dim().z(); ++z) {
            const std::vector<std::uint8_t> slice(active.begin() + z * sliceSize, active.begin() + (z + 1) * sliceSize);
            const SliceCounts counts = countSlice(slice, size.x(), size.y());
            total.enclosedInactive += counts.enclosedInactive;
            total.inside += counts.inside;
        }
    }
    return total.inside > 0 ? double(total.enclosedInactive) / double(total.inside) : 0.0;
}

}  // namespace gvr
