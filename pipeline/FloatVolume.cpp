#include "pipeline/FloatVolume.h"

#include "pipeline/Error.h"
#include "pipeline/Trilinear.h"
#include "pipeline/VolumeMetadata.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace gvr {

FloatVolume::FloatVolume(const openvdb::Coord& size, int channelCount)
    : dims(size), channels(channelCount), values(voxelCount() * std::size_t(channelCount), 0.0f) {}

openvdb::CoordBBox volumeBox(const openvdb::GridBase& grid) {
    if (const auto metadata = readVolumeMetadata(grid)) {
        return openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(metadata->dims) - openvdb::Coord(1));
    }
    return grid.evalActiveVoxelBoundingBox();
}

namespace {

template <typename GridT, typename Store>
void copyGridValues(const GridT& grid, const openvdb::CoordBBox& box, FloatVolume& volume, Store store) {
    tbb::parallel_for(0, volume.dims.z(), [&](int k) {
        auto accessor = grid.getConstAccessor();
        for (int j = 0; j < volume.dims.y(); ++j) {
            for (int i = 0; i < volume.dims.x(); ++i) {
                const openvdb::Coord ijk = box.min().offsetBy(i, j, k);
                store(accessor.getValue(ijk), volume.at(i, j, k));
                volume.foreground[volume.indexOf(i, j, k)] = accessor.isValueOn(ijk) ? 1 : 0;
            }
        }
    });
}

}  // namespace

FloatVolume sampleGrid(const openvdb::GridBase& grid, const openvdb::CoordBBox& box) {
    const int channels = grid.isType<openvdb::Vec3SGrid>() ? 3 : 1;
    FloatVolume volume(box.empty() ? openvdb::Coord(0) : box.dim(), channels);
    volume.foreground.assign(volume.voxelCount(), 0);
    openvdb::math::Mat4d offset = openvdb::math::Mat4d::identity();
    offset.setTranslation(box.min().asVec3d());
    volume.worldFromIndex = offset * grid.transform().baseMap()->getAffineMap()->getMat4();
    if (volume.voxelCount() == 0) return volume;
    if (const auto* floats = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
        copyGridValues(*floats, box, volume, [](float v, float* out) { out[0] = v; });
    } else if (const auto* doubles = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
        copyGridValues(*doubles, box, volume, [](double v, float* out) { out[0] = float(v); });
    } else if (const auto* colours = dynamic_cast<const openvdb::Vec3SGrid*>(&grid)) {
        copyGridValues(*colours, box, volume, [](const openvdb::Vec3s& v, float* out) {
            for (int c = 0; c < 3; ++c) out[c] = v[c];
        });
    } else {
        throw InputError("grid '" + grid.getName() + "'",
                         "holds " + grid.valueType() + "; gvr reads float, double or vec3s grids");
    }
    return volume;
}

FloatVolume resampleTrilinear(const FloatVolume& source, const openvdb::Coord& dims,
                              const openvdb::math::Mat4d& worldFromIndex) {
    FloatVolume out(dims, source.channels);
    out.worldFromIndex = worldFromIndex;
    const openvdb::math::Mat4d sourceFromTarget = worldFromIndex * source.worldFromIndex.inverse();
    const auto clampTo = [](int v, int size) { return std::clamp(v, 0, size - 1); };
    tbb::parallel_for(0, dims.z(), [&](int k) {
        for (int j = 0; j < dims.y(); ++j) {
            for (int i = 0; i < dims.x(); ++i) {
                openvdb::Vec3d x = sourceFromTarget.transform(openvdb::Vec3d(i, j, k));
                // Clamped before the int conversion, which far-away positions would overflow.
                for (int a = 0; a < 3; ++a) x[a] = std::clamp(x[a], -1.0, double(source.dims[a]));
                float* value = out.at(i, j, k);
                forEachTrilinearCorner(x, [&](const openvdb::Coord& corner, double weight) {
                    const float* sample =
                        source.at(clampTo(corner.x(), source.dims.x()), clampTo(corner.y(), source.dims.y()),
                                  clampTo(corner.z(), source.dims.z()));
                    for (int c = 0; c < source.channels; ++c) value[c] += float(weight * sample[c]);
                });
            }
        }
    });
    return out;
}

}  // namespace gvr
