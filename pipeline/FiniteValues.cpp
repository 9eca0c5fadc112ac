#include "pipeline/FiniteValues.h"

#include "pipeline/Error.h"

#include <tbb/parallel_reduce.h>

#include <cmath>
#include <sstream>
#include <vector>

namespace gvr {

namespace {

bool finite(float v) { return std::isfinite(v); }
bool finite(double v) { return std::isfinite(v); }
bool finite(const openvdb::Vec3s& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

/// Non-finite values found, and the least coordinate among them (for the message).
struct Found {
    std::uint64_t count = 0;
    openvdb::Coord first = openvdb::Coord::max();

    void add(const openvdb::Coord& ijk) {
        ++count;
        if (ijk < first) first = ijk;
    }
    void join(const Found& other) {
        count += other.count;
        if (other.count > 0 && other.first < first) first = other.first;
    }
};

template <typename GridT>
Found nonFiniteValues(const GridT& grid, const std::optional<openvdb::CoordBBox>& region) {
    using TreeT = typename GridT::TreeType;
    using LeafT = typename TreeT::LeafNodeType;
    const auto touches = [&](const openvdb::CoordBBox& box) { return !region || region->hasOverlap(box); };
    Found found;
    // Tiles above the leaves: few, so one thread.
    typename TreeT::ValueAllCIter tile = grid.tree().cbeginValueAll();
    tile.setMaxDepth(TreeT::ValueAllCIter::LEAF_DEPTH - 1);
    for (; tile; ++tile) {
        openvdb::CoordBBox box;
        tile.getBoundingBox(box);
        if (!finite(*tile) && touches(box)) found.add(box.min());
    }
    std::vector<const LeafT*> leaves;
    grid.tree().getNodes(leaves);
    const Found inLeaves = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, leaves.size()), Found{},
        [&](const tbb::blocked_range<std::size_t>& range, Found part) {
            for (std::size_t n = range.begin(); n < range.end(); ++n) {
                const LeafT& leaf = *leaves[n];
                if (!touches(leaf.getNodeBoundingBox())) continue;
                for (openvdb::Index v = 0; v < LeafT::SIZE; ++v) {
                    if (!finite(leaf.getValue(v))) part.add(leaf.offsetToGlobalCoord(v));
                }
            }
            return part;
        },
        [](Found a, const Found& b) {
            a.join(b);
            return a;
        });
    found.join(inLeaves);
    return found;
}

template <typename GridT>
void requireFiniteValuesOf(const GridT& grid, const std::string& name,
                           const std::optional<openvdb::CoordBBox>& region) {
    const std::string which = "grid '" + grid.getName() + "'";
    if (!finite(grid.background())) {
        throw InputError(name, which + " has a NaN or infinite background; ingest it again with `nan_to=VALUE`");
    }
    const Found found = nonFiniteValues(grid, region);
    if (found.count == 0) return;
    std::ostringstream text;
    text << which << " holds " << found.count << " NaN or infinite value" << (found.count == 1 ? "" : "s")
         << " (the first at voxel " << found.first << "); ingest it again with `nan_to=VALUE` to replace them";
    throw InputError(name, text.str());
}

}  // namespace

void requireFiniteValues(const openvdb::GridBase& grid, const std::string& name,
                         const std::optional<openvdb::CoordBBox>& region) {
    if (const auto* floats = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
        requireFiniteValuesOf(*floats, name, region);
    } else if (const auto* doubles = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
        requireFiniteValuesOf(*doubles, name, region);
    } else if (const auto* colours = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) {
        requireFiniteValuesOf(*colours, name, region);
    }
}

}  // namespace gvr
