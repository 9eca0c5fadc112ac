#include "EnclosedShare.h"

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
    const openvdb::Coord size = box.dim();
    // The active voxels as one flag per voxel, filled leaf by leaf through the tree's mask.
    openvdb::MaskGrid mask;
    grid.apply<openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid, openvdb::Vec3SGrid, openvdb::Int32Grid>>(
        [&](const auto& typed) { mask.topologyUnion(typed); });
    std::vector<std::uint8_t> active(std::size_t(size.x()) * size.y() * size.z(), 0);
    for (auto on = mask.cbeginValueOn(); on; ++on) {
        openvdb::CoordBBox voxels;
        on.getBoundingBox(voxels);
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            const openvdb::Coord at = *ijk - box.min();
            active[(std::size_t(at.z()) * size.y() + at.y()) * size.x() + at.x()] = 1;
        }
    }
    SliceCounts total;
    const std::size_t sliceSize = std::size_t(size.x()) * size.y();
    for (int z = 0; z < size.z(); ++z) {
        const std::vector<std::uint8_t> slice(active.begin() + z * sliceSize, active.begin() + (z + 1) * sliceSize);
        const SliceCounts counts = countSlice(slice, size.x(), size.y());
        total.enclosedInactive += counts.enclosedInactive;
        total.inside += counts.inside;
    }
    return total.inside > 0 ? double(total.enclosedInactive) / double(total.inside) : 0.0;
}

}  // namespace gvr
