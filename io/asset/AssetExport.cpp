#include "io/asset/AssetExport.h"

#include "io/Ingest.h"
#include "io/asset/AssetResidual.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/Luminance.h"
#include "pipeline/ThresholdCut.h"
#include "pipeline/VolumeBorder.h"

#include <openvdb/tools/Dense.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

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

/// Blender and Houdini interpolate colour and density alike: where a structure ends,
/// the colour fell to the inactive voxels' black as the density fell to zero, so
/// the light emitted (their product) fell twice as fast, and thin bone came out
/// darker in Blender than in gvr render. The colour reaches one voxel further, each
/// new voxel the mean colour of its active neighbours, where the density stays zero.
void extendColourOneVoxel(openvdb::Vec3SGrid& colour) {
    openvdb::MaskGrid reach(false);
    reach.topologyUnion(colour);
    openvdb::tools::dilateActiveValues(reach.tree(), 1, openvdb::tools::NN_FACE_EDGE_VERTEX);
    const auto original = colour.getConstAccessor();
    std::vector<std::pair<openvdb::Coord, openvdb::Vec3s>> added;
    for (auto voxel = reach.cbeginValueOn(); voxel; ++voxel) {
        const openvdb::Coord at = voxel.getCoord();
        if (original.isValueOn(at)) continue;
        openvdb::Vec3s sum(0.0f);
        int count = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const openvdb::Coord next = at.offsetBy(dx, dy, dz);
                    if (original.isValueOn(next)) sum += original.getValue(next), ++count;
                }
        if (count > 0) added.emplace_back(at, sum / float(count));
    }
    auto colours = colour.getAccessor();
    for (const auto& [at, rgb] : added) colours.setValueOn(at, rgb);
}

/// The DCC tools' grids on @a values' active voxels: density (the opacity of the
/// style's transfer function) and colour in 0..1, with the world in metres.
template <typename GridT>
openvdb::GridPtrVec dccGrids(const GridT& values, const DccStyle& style, GridNaming naming) {
    auto density = openvdb::FloatGrid::create(0.0f);
    density->setTree(std::make_shared<openvdb::FloatTree>(values.tree(), 0.0f, openvdb::TopologyCopy()));
    auto colour = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
    colour->setTree(std::make_shared<openvdb::Vec3STree>(values.tree(), openvdb::Vec3s(0.0f), openvdb::TopologyCopy()));
    auto densities = density->getAccessor();
    auto colours = colour->getAccessor();
    for (auto voxel = values.cbeginValueOn(); voxel; ++voxel) {
        const auto value = *voxel;
        openvdb::Vec3s rgb;
        float opacity;
        if constexpr (std::is_same_v<typename GridT::ValueType, openvdb::Vec3s>) {
            opacity = style.transfer(luminance(value))[3];
            for (int c = 0; c < 3; ++c) rgb[c] = float(std::clamp(value[c] * style.colourScale, 0.0, 1.0));
        } else {
            const std::array<float, 4> rgba = style.transfer(value);
            opacity = rgba[3];
            rgb = openvdb::Vec3s(rgba[0], rgba[1], rgba[2]);
        }
        if (!(opacity > 0.0f)) {  // transparent: nothing for the renderer to step through
            densities.setValueOff(voxel.getCoord(), 0.0f);
            colours.setValueOff(voxel.getCoord(), openvdb::Vec3s(0.0f));
            continue;
        }
        densities.setValueOnly(voxel.getCoord(), std::min(opacity, 1.0f));
        colours.setValueOnly(voxel.getCoord(), rgb);
    }
    openvdb::tools::pruneInactive(density->tree());
    openvdb::tools::pruneInactive(colour->tree());
    extendColourOneVoxel(*colour);
    openvdb::math::Transform::Ptr metres = values.transform().copy();
    metres->postScale(1e-3);  // Blender and Houdini take one unit as one metre
    density->setTransform(metres);
    colour->setTransform(metres->copy());
    density->setName("density");
    colour->setName(naming == GridNaming::Houdini ? "Cd" : "color");
    return {density, colour};
}

void describe(openvdb::GridBase& grid, const GaussianAsset& asset, const ExportResult& result,
              const std::string& assetPath) {
    VolumeMetadata metadata = asset.source;
    metadata.dims = openvdb::Vec3i(result.lattice.box.dim().asVec3i());
    metadata.spacingMm = axisSpacing(result.lattice.worldFromIndex);
    metadata.threshold = result.threshold;
    metadata.thresholdAbove = result.thresholdAbove;
    writeVolumeMetadata(metadata, grid);
    grid.insertMeta("gvr_exported_from", openvdb::StringMetadata(assetPath));
}

/// What a DCC user needs to set up a material by hand: a naive import showed
/// nothing, since density 0..1 a voxel is far too thin per metre, and a 0.36 m
/// chest was a speck in a scene built for 2 m objects.
void describeForDcc(openvdb::GridBase& grid, const Lattice& lattice) {
    const openvdb::Vec3d spacingM = axisSpacing(lattice.worldFromIndex) * 1e-3;
    const openvdb::Vec3d extentM = spacingM * lattice.box.dim().asVec3d();
    const double voxelM = std::min({spacingM[0], spacingM[1], spacingM[2]});
    grid.insertMeta("gvr_units", openvdb::StringMetadata(kDccUnits));
    // Extinction per metre = -ln(1 - density) * this; about density * this where thin.
    grid.insertMeta("gvr_density_scale", openvdb::DoubleMetadata(1.0 / voxelM));
    grid.insertMeta("gvr_object_size_m", openvdb::DoubleMetadata(std::max({extentM[0], extentM[1], extentM[2]})));
}

/// @a volume as a grid on @a lattice, every voxel active: a bounded reconstruction
/// holds its bound on every voxel, the background's included.
openvdb::GridBase::Ptr gridOfEveryVoxel(const FloatVolume& volume, const Lattice& lattice, double background) {
    const auto placed = [&](auto grid) {
        grid->setTransform(openvdb::math::Transform::createLinearTransform(lattice.worldFromIndex));
        return grid;
    };
    // A negative tolerance: no value is "equal to the background", so every voxel is set
    // active. LayoutXYZ is OpenVDB's name for x fastest, as FloatVolume runs.
    constexpr float kEveryVoxel = -1.0f;
    if (volume.channels == 1) {
        auto grid = openvdb::FloatGrid::create(float(background));
        openvdb::tools::Dense<const float, openvdb::tools::LayoutXYZ> dense(lattice.box, volume.values.data());
        openvdb::tools::copyFromDense(dense, *grid, kEveryVoxel);
        grid->setName("density");
        return placed(grid);
    }
    auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(float(background)));
    const auto* rgb = reinterpret_cast<const openvdb::Vec3s*>(volume.values.data());
    openvdb::tools::Dense<const openvdb::Vec3s, openvdb::tools::LayoutXYZ> dense(lattice.box, rgb);
    openvdb::tools::copyFromDense(dense, *grid, openvdb::Vec3s(kEveryVoxel));
    grid->setName("color");
    return placed(grid);
}

bool isSourceLattice(const Lattice& lattice, const GaussianAsset& asset) {
    const Lattice own = sourceLattice(asset.worldFromIndex, asset.source.dims);
    return lattice.box == own.box && lattice.worldFromIndex == own.worldFromIndex;
}

}  // namespace

AssetLayers parseAssetLayers(const std::string& text, const std::string& name) {
    if (text == "all") return AssetLayers::All;
    if (text == "gaussians") return AssetLayers::Gaussians;
    throw InputError(name, "must be all or gaussians, not '" + text + "'");
}

FloatVolume gaussianPrediction(const GaussianAsset& asset, const ProgressFn& progress) {
    const Lattice lattice = sourceLattice(asset.worldFromIndex, asset.source.dims);
    const GaussianField field(asset.params, asset.cutoffSigmas);
    const FieldToGridSettings sampling{asset.mapping, std::nullopt, std::nullopt, lattice.box};
    const openvdb::GridBase::Ptr grid = fieldToGrid(field, asset.worldFromIndex, lattice, sampling, progress);
    return sampleGrid(*grid, lattice.box);
}

FloatVolume boundedReconstruction(const GaussianAsset& asset, const std::string& name, const ProgressFn& progress) {
    if (!asset.residual) throw std::logic_error("boundedReconstruction needs an asset with a residual layer");
    FloatVolume reconstruction = decodeResidualLayer(*asset.residual, gaussianPrediction(asset, progress));
    if (reconstructionChecksum(reconstruction) != asset.residual->reconstructionChecksum) {
        throw InputError(name,
                         "its residual layer decodes to other values than when it was written (the "
                         "Gaussians' field differs in the last bits on this machine), so its bound is not "
                         "known to hold; export with the Gaussians alone, or fit again here");
    }
    return reconstruction;
}

ExportResult exportAsset(const GaussianAsset& asset, const ExportSettings& settings, const ProgressFn& progress) {
    if (settings.dcc && settings.densityFrom) {
        throw InputError("`density_from`", "does not combine with `dcc`, whose transfer function gives the density");
    }
    if (settings.densityFrom && asset.params.channels != 3) {
        throw InputError("`density_from`", "applies to RGB assets only; this asset is grey");
    }
    const openvdb::Vec3i dims = asset.source.dims;
    ExportResult result;
    result.lattice = settings.lattice.value_or(sourceLattice(asset.worldFromIndex, dims));
    if (settings.threshold && std::isnan(*settings.threshold))
        throw InputError("`threshold`", "must be a number, not NaN");
    result.threshold = settings.threshold.value_or(defaultExportThreshold(asset.source));
    result.thresholdAbove = defaultExportThresholdAbove(asset.source);
    const openvdb::Coord size = result.lattice.box.dim();
    checkVolumeFitsInMemory(settings.assetPath.empty() ? "asset" : settings.assetPath, {size.x(), size.y(), size.z()},
                            asset.params.channels, sizeof(float), "export");
    const std::string name = settings.assetPath.empty() ? "asset" : settings.assetPath;
    openvdb::GridBase::Ptr values;
    if (readsResidualLayer(asset, settings.layers)) {
        if (!isSourceLattice(result.lattice, asset)) {
            throw InputError(name,
                             "its residual layer holds its bound on the source's own grid only; export "
                             "there, or the Gaussians alone (`layers` gaussians) on another grid");
        }
        result.threshold = std::numeric_limits<float>::lowest();  // every voxel is kept
        result.thresholdAbove.reset();
        values =
            gridOfEveryVoxel(boundedReconstruction(asset, name, progress), result.lattice, asset.source.background);
    } else {
        const GaussianField field(asset.params, asset.cutoffSigmas);
        const FieldToGridSettings sampling{asset.mapping, result.threshold, result.thresholdAbove,
                                           sourceLattice(asset.worldFromIndex, dims).box};
        values = fieldToGrid(field, asset.worldFromIndex, result.lattice, sampling, progress);
    }
    if (settings.dcc) {
        if (auto grey = openvdb::GridBase::grid<openvdb::FloatGrid>(values)) {
            result.grids = dccGrids(*grey, *settings.dcc, settings.naming);
        } else {
            result.grids =
                dccGrids(*openvdb::GridBase::grid<openvdb::Vec3SGrid>(values), *settings.dcc, settings.naming);
        }
    } else {
        result.grids.push_back(values);
    }
    if (auto colour = settings.dcc ? nullptr : openvdb::GridBase::grid<openvdb::Vec3SGrid>(values)) {
        if (settings.naming == GridNaming::Houdini) colour->setName("Cd");
        auto density = derivedDensity(*colour, result.lattice.box, asset, settings);
        density->setName("density");
        result.grids.push_back(density);
    }
    for (auto& grid : result.grids) {
        if (grid->getName() == "density") grid->setGridClass(openvdb::GRID_FOG_VOLUME);
        describe(*grid, asset, result, settings.assetPath);
        if (settings.dcc) describeForDcc(*grid, result.lattice);
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

Lattice latticeLike(const std::string& path) { return latticeOf(*loadOrIngest(path, IngestOptions{}).grid, path); }

}  // namespace gvr
