// An existing .vdb file: its first scalar or colour grid, densified over the grid's
// active bounding box so that it takes the same path through ingest as any scan.

#include "io/formats/GridFile.h"
#include "io/formats/Readers.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

namespace gvr {

namespace {

template <typename GridT>
void copyToDense(const GridT& grid, const openvdb::CoordBBox& box, DenseVolume& volume) {
    using Value = typename GridT::ValueType;
    auto accessor = grid.getConstAccessor();
    float* out = volume.data<float>();
    std::size_t sample = 0;
    for (int k = box.min().z(); k <= box.max().z(); ++k) {
        for (int j = box.min().y(); j <= box.max().y(); ++j) {
            for (int i = box.min().x(); i <= box.max().x(); ++i) {
                const Value value = accessor.getValue(openvdb::Coord(i, j, k));
                if constexpr (std::is_same_v<Value, openvdb::Vec3s>) {
                    for (int c = 0; c < 3; ++c) out[sample++] = value[c];
                } else {
                    out[sample++] = float(value);
                }
            }
        }
    }
}

}  // namespace

DenseVolume readVdb(const std::string& path, const ReadOptions& options) {
    const openvdb::GridPtrVecPtr grids = readGridFile(path);
    const openvdb::GridBase::Ptr grid = chooseVolumeGrid(*grids, path);
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) throw InputError(path, "grid '" + grid->getName() + "' has no active voxels");

    DenseVolume volume;
    // In 64 bits: a corrupt file's box may span more than an int can count, which
    // the memory check below then refuses.
    for (int axis = 0; axis < 3; ++axis) volume.dims[axis] = std::int64_t(box.max()[axis]) - box.min()[axis] + 1;
    volume.type = SampleType::Float32;
    volume.channels = grid->isType<openvdb::Vec3SGrid>() ? 3 : 1;
    if (const auto metadata = readVolumeMetadata(*grid)) volume.modality = metadata->modality;
    // Dense index 0 sits at the box's minimum corner.
    volume.worldFromIndex = openvdb::math::Mat4d::identity();
    volume.worldFromIndex.setTranslation(openvdb::Vec3d(box.min().asVec3d()));
    volume.worldFromIndex = volume.worldFromIndex * grid->transform().baseMap()->getAffineMap()->getMat4();
    allocateSamples(volume, path);

    if (auto floats = openvdb::GridBase::grid<openvdb::FloatGrid>(grid)) {
        copyToDense(*floats, box, volume);
    } else if (auto doubles = openvdb::GridBase::grid<openvdb::DoubleGrid>(grid)) {
        copyToDense(*doubles, box, volume);
    } else {
        copyToDense(*openvdb::GridBase::grid<openvdb::Vec3SGrid>(grid), box, volume);
    }
    if (options.progress) options.progress(1.0);
    return volume;
}

}  // namespace gvr
