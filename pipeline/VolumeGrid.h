/// @file VolumeGrid.h
/// @brief The grids that gvr fits, renders and compresses: float (grey) and vec3s
/// (RGB), as ingest writes them; the one list, and the one message for the rest.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

namespace gvr {

inline bool isVolumeGrid(const openvdb::GridBase& grid) {
    return grid.isType<openvdb::FloatGrid>() || grid.isType<openvdb::Vec3SGrid>();
}

/// Why @a grid is no volume grid, for an InputError about it.
inline std::string notAVolumeGrid(const openvdb::GridBase& grid) {
    return "grid '" + grid.getName() + "' holds " + grid.valueType() +
           "; gvr works on float (grey) and vec3s (RGB) grids, as ingest writes them";
}

}  // namespace gvr
