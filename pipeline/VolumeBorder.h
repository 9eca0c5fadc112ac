/// @file VolumeBorder.h
/// @brief What surrounds the subject of a volume: the typical value on its faces.
///
/// For photographed sections that is the paper or the embedding medium, however
/// bright, rather than the dark minimum that ingest made background; for CT and MRI
/// it is air. Renderers and export both treat it as "nothing here".
#pragma once

#include <openvdb/openvdb.h>

#include <algorithm>
#include <vector>

namespace gvr {

/// The median of @a key(ijk) over a grid of about 64 x 64 voxels on each face of @a box.
template <typename Key>
double borderMedian(const openvdb::CoordBBox& box, const Key& key) {
    std::vector<double> values;
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const int stepU = std::max(1, box.dim()[u] / 64), stepV = std::max(1, box.dim()[v] / 64);
        for (const int side : {box.min()[axis], box.max()[axis]}) {
            for (int a = box.min()[u]; a <= box.max()[u]; a += stepU) {
                for (int b = box.min()[v]; b <= box.max()[v]; b += stepV) {
                    openvdb::Coord ijk;
                    ijk[axis] = side;
                    ijk[u] = a;
                    ijk[v] = b;
                    values.push_back(key(ijk));
                }
            }
        }
    }
    if (values.empty()) return 0.0;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
    return values[values.size() / 2];
}

}  // namespace gvr
