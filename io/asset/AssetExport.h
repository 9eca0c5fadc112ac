/// @file AssetExport.h
/// @brief A Gaussian asset back to grids that Blender, Houdini and medical tools open.
#pragma once

#include "pipeline/FieldToGrid.h"
#include "pipeline/GaussianAsset.h"
#include "pipeline/TransferFunction.h"

#include <openvdb/openvdb.h>

#include <optional>
#include <string>

namespace gvr {

/// Colour grid names: Blender reads "color", Houdini "Cd". Both read "density".
enum class GridNaming { Blender, Houdini };

/// What DCC tools (Blender, Houdini) render well without a hand-made material:
/// density in 0..1 as this transfer function's opacity (at the value, or the
/// luminance for RGB), colour in 0..1 (the transfer function's for grey data, the
/// data's times colourScale for RGB), and the world in metres.
/// The gvr_units metadata of a DCC export's grids, whose world unit is the metre
/// where gvr's is the millimetre. They also carry gvr_density_scale (per metre: the
/// extinction is -ln(1 - density) times it) and gvr_object_size_m (the longest side).
inline constexpr const char* kDccUnits = "metres; density and colour 0..1";

struct DccStyle {
    TransferFunction transfer;
    double colourScale = 1.0 / 255.0;
};

/// Which of an asset's layers a reader uses.
enum class AssetLayers {
    All,        ///< the Gaussians and the residual layer of fit --max-error, when there is one
    Gaussians,  ///< the Gaussians alone: the preview
};

/// "all" or "gaussians", as `--layers` and `layers=` give it.
/// @throw InputError naming @a name for anything else.
AssetLayers parseAssetLayers(const std::string& text, const std::string& name);

/// True when a reader of @a layers of @a asset reads a residual layer.
inline bool readsResidualLayer(const GaussianAsset& asset, AssetLayers layers) {
    return asset.residual && layers == AssetLayers::All;
}

struct ExportSettings {
    std::optional<Lattice> lattice;  ///< unset: the source's own grid
    /// Physical units (luminance for RGB); voxels at or below stay inactive.
    /// Unset: defaultExportThreshold() (midway between the background and the ingest threshold).
    std::optional<double> threshold;
    GridNaming naming = GridNaming::Blender;
    /// RGB only: density = this function's opacity at each voxel's luminance.
    /// Unset: how far the luminance lies from what surrounds the subject (the median
    /// luminance on the grid's faces: white paper or black medium), in units of the
    /// source's luminance range.
    std::optional<TransferFunction> densityFrom;
    std::string assetPath;  ///< recorded in the grids' metadata
    /// Set: the grids in DccStyle (density first, then colour) instead of physical units.
    std::optional<DccStyle> dcc;
    AssetLayers layers = AssetLayers::All;
};

struct ExportResult {
    openvdb::GridPtrVec grids;  ///< the value grid first, then a derived density for RGB
    Lattice lattice;
    double threshold = 0.0;
    std::optional<double> thresholdAbove;  ///< from a source cut from above too
};

/// Evaluates the asset's field at the lattice's voxel centres (see fieldToGrid),
/// with its own cutoff; or, when it reads a residual layer (readsResidualLayer), its bounded reconstruction on the source's lattice, every
/// voxel active, so that every voxel is within the layer's bound of the source. Grey data gives a float fog volume "density" in physical
/// units; RGB a Vec3s "color" (or "Cd") plus a float fog volume "density". Every
/// grid carries the source's metadata, with the lattice's dimensions and spacing.
ExportResult exportAsset(const GaussianAsset& asset, const ExportSettings& settings, const ProgressFn& progress = {});

/// The Gaussians alone at every voxel of the source's lattice (no threshold): what
/// a residual layer is encoded over and decoded onto.
FloatVolume gaussianPrediction(const GaussianAsset& asset, const ProgressFn& progress = {});

/// The asset's residual layer decoded onto gaussianPrediction(): every voxel within
/// its bound of the source. @throw InputError naming @a name when the result is not
/// bit for bit what the encoder decoded (its checksum), since the bound then is not
/// known to hold.
FloatVolume boundedReconstruction(const GaussianAsset& asset, const std::string& name, const ProgressFn& progress = {});

/// The lattice of @a grid (its gvr dimensions, or its active voxels), moved so that
/// its first voxel has index (0, 0, 0). @throw InputError naming @a name when it has
/// no voxels.
Lattice latticeOf(const openvdb::GridBase& grid, const std::string& name);

/// The lattice of the volume in @a path (a .vdb, or anything ingest reads), moved so
/// that its first voxel has index (0, 0, 0).
/// @throw InputError naming @a path when it cannot be read or holds no voxels.
Lattice latticeLike(const std::string& path);

}  // namespace gvr
