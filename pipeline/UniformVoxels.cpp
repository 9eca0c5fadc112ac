#include "pipeline/UniformVoxels.h"

#include <algorithm>
#include <random>

namespace gvr {

std::vector<openvdb::Coord> drawUniformVoxels(const openvdb::CoordBBox& box, std::size_t count, std::uint64_t seed) {
    std::vector<openvdb::Coord> voxels;
    if (box.empty()) return voxels;
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    voxels.resize(count);
    for (openvdb::Coord& ijk : voxels) {
        for (int axis = 0; axis < 3; ++axis) {
            const int span = box.max()[axis] - box.min()[axis] + 1;
            ijk[axis] = box.min()[axis] + std::min(int(unit(random) * span), span - 1);
        }
    }
    return voxels;
}

}  // namespace gvr
