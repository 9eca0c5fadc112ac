#include "AssetExport.h"

#include "Error.h"
#include "FloatVolume.h"
#include "Ingest.h"
#include "Luminance.h"
#include "MemoryBudget.h"
#include "ThresholdCut.h"
#include "VolumeBorder.h"

namespace gvr {

namespace {

/// A float fog volume with the colour grid's active voxels, each voxel's density
/// taken from its physical colour: by default how far its luminance lies from what
/// surrounds the subject (white paper or black medium alike), in the source's range.
openvdb::FloatGrid::Ptr derivedDensity(const openvdb::Vec3SGrid& colour, const openvdb::CoordBBox& box,
                                       const GaussianAsset& asset, const ExportSettings& settings) {
    const auto colours = colour.getConstAccessor();
    const double backgroundLuminance =
        borderMedian(box, [&](const openvdb::Coord& ijk) { return luminance(colours.getValue(ijk)); });
    auto density = openvdb::FloatGrid::create(0.0f);
    density->setTree(std::make_shared<openvdb::FloatTree>(colour.tree(), 0.0f, openvdb::TopologyCopy()));
    density->setTransform(colour.transform().copy());
    auto accessor = density->getAccessor();
    for (auto voxel = colour.cbeginValueOn(); voxel; ++voxel) {
        const double lum = luminance(*voxel);
        const float value = settings.densityFrom ? (*settings.densityFrom)(lum)[3]
                                                 : float(std::abs(lum - backgroundLuminance) / asset.mapping.scale);
        accessor.setValueOnly(voxel.getCoord(), value);
    }
    return density;
}

void describe(openvdb::GridBase& grid, const GaussianAsset& asset, const ExportResult& result,
              const std::string& assetPath) {
    VolumeMetadata metadata = asset.source;
    metadata.dims = openvdb::Vec3i(result.lattice.box.dim().asVec3i());
    metadata.spacingMm = axisSpacing(result.lattice.worldFromIndex);
    metadata.threshold = result.threshold;
    writeVolumeMetadata(metadata, grid);
    grid.insertMeta("gvr_exported_from", openvdb::StringMetadata(assetPath));
}

}  // namespace

ExportResult exportAsset(const GaussianAsset& asset, const ExportSettings& settings, const ProgressFn& progress) {
    if (settings.densityFrom && asset.params.channels != 3) {
        throw InputError("--density-from", "applies to RGB assets only; this asset is grey");
    }
    const openvdb::Vec3i dims = asset.source.dims;
    ExportResult result;
    result.lattice = settings.lattice.value_or(sourceLattice(asset.worldFromIndex, dims));
    result.threshold = settings.threshold.value_or(defaultExportThreshold(asset.source));
    const openvdb::Coord size = result.lattice.box.dim();
    checkVolumeFitsInMemory(settings.assetPath.empty() ? "asset" : settings.assetPath, {size.x(), size.y(), size.z()},
                            asset.params.channels, sizeof(float), "export");
    const GaussianField field(asset.params, asset.cutoffSigmas);
    const FieldToGridSettings sampling{asset.mapping, result.threshold, sourceLattice(asset.worldFromIndex, dims).box};
    openvdb::GridBase::Ptr values = fieldToGrid(field, asset.worldFromIndex, result.lattice, sampling, progress);
    result.grids.push_back(values);
    if (auto colour = openvdb::GridBase::grid<openvdb::Vec3SGrid>(values)) {
        if (settings.naming == GridNaming::Houdini) colour->setName("Cd");
        auto density = derivedDensity(*colour, result.lattice.box, asset, settings);
        density->setName("density");
        result.grids.push_back(density);
    }
    for (auto& grid : result.grids) {
        if (grid->getName() == "density") grid->setGridClass(openvdb::GRID_FOG_VOLUME);
        describe(*grid, asset, result, settings.assetPath);
    }
    return result;
}

Lattice latticeOf(const openvdb::GridBase& grid, const std::string& name) {
    const openvdb::CoordBBox box = volumeBox(grid);
    if (box.empty()) throw InputError(name, "grid '" + grid.getName() + "' has no voxels to take a lattice from");
    openvdb::math::Mat4d shift = openvdb::math::Mat4d::identity();
    shift.setTranslation(box.min().asVec3d());
    const openvdb::math::Mat4d worldFromIndex = grid.transform().baseMap()->getAffineMap()->getMat4();
    return {shift * worldFromIndex, openvdb::CoordBBox(openvdb::Coord(0), box.dim() - openvdb::Coord(1))};
}

Lattice latticeLike(const std::string& path) {
    return latticeOf(*loadOrIngest(path, IngestOptions{}).grid, path);
}

}  // namespace gvr
