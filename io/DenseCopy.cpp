#include "io/DenseCopy.h"

#include "io/guard/MemoryBudget.h"

namespace gvr {

FloatVolume denseCopy(const openvdb::GridBase& grid, const openvdb::CoordBBox& box, const std::string& file,
                      const std::string& task) {
    if (!box.empty()) {
        const openvdb::Coord size = box.dim();
        const int channels = grid.isType<openvdb::Vec3SGrid>() ? 3 : 1;
        // The float samples, and a byte a voxel for the foreground mask.
        checkVolumeFitsInMemory(file, {size.x(), size.y(), size.z()}, channels, 1, task);
    }
    return sampleGrid(grid, box);
}

}  // namespace gvr
