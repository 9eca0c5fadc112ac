// gvr export ASSET -o OUT.vdb [-o OUT.nii.gz]: the reconstruction as OpenVDB grids and/or NIfTI.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/GridSummary.h"
#include "cli/LayersOption.h"
#include "cli/ProgressBar.h"
#include "cli/VolumeOutputOptions.h"
#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/formats/JsonText.h"
#include "io/formats/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "workflow/RenderInput.h"

#include <chrono>
#include <iostream>

namespace gvr {

namespace {

struct ExportFlags {
    std::string input, like, names = "blender", densityFrom, removedFormat, show, hide, tf, layers = "all";
    std::vector<std::string> outputs;
    std::optional<double> voxelSize, threshold;
    std::optional<int> resolution;
    bool float32 = false, dcc = false, json = false, quiet = false;
};

std::optional<Lattice> chosenLattice(const ExportFlags& flags, const GaussianAsset& asset) {
    if (!flags.like.empty()) return latticeLike(flags.like);
    if (flags.resolution) {
        const double voxelSize = voxelSizeForResolution(asset.worldFromIndex, asset.source.dims, *flags.resolution);
        try {
            return resizedLattice(asset.worldFromIndex, asset.source.dims, voxelSize);
        } catch (const InputError&) {  // it names the voxel size, which this user did not give
            throw InputError("--resolution", std::to_string(*flags.resolution) +
                                                 " voxels along the longest axis would need more than 2^36 voxels");
        }
    }
    if (flags.voxelSize) return resizedLattice(asset.worldFromIndex, asset.source.dims, *flags.voxelSize);
    return std::nullopt;
}

/// --dcc: the transfer function of --tf (as render takes it) over the asset's
/// field, and RGB scaled as the renderer scales it.
DccStyle dccStyleFor(const ExportFlags& flags, const GaussianAsset& asset) {
    for (const std::string& output : flags.outputs) {
        if (volumeFileFormat(output) != VolumeFileFormat::Vdb) {
            throw InputError("--dcc", "writes OpenVDB for Blender and Houdini: give -o OUT.vdb, not " + output);
        }
    }
    const GaussianRenderVolume volume(asset);
    std::string mismatch;
    DccStyle style{transferFunctionFor(flags.tf, volume, &mismatch), 1.0 / volume.valueMax()};
    if (!mismatch.empty()) diagnostics() << "gvr: warning: --tf: " << mismatch << "\n";
    return style;
}

void runExport(const ExportFlags& flags) {
    rejectRemovedFormat(flags.removedFormat);
    checkVolumeOutputs("-o", flags.outputs, {flags.input, flags.like, flags.densityFrom, flags.tf});
    const auto start = std::chrono::steady_clock::now();
    const GaussianAsset asset = selectStructures(readAsset(flags.input), flags.show, flags.hide, flags.input);
    ExportSettings settings;
    settings.layers = parseAssetLayers(flags.layers, "--layers");
    const bool bounded = readsResidualLayer(asset, settings.layers);
    if (bounded && flags.threshold) {
        throw InputError("--threshold",
                         "the residual layer keeps every voxel within its bound, so there is "
                         "nothing to cut; add --layers gaussians to cut the Gaussians alone");
    }
    settings.lattice = chosenLattice(flags, asset);
    settings.threshold = flags.threshold;
    settings.naming = flags.names == "houdini" ? GridNaming::Houdini : GridNaming::Blender;
    if (!flags.densityFrom.empty()) settings.densityFrom = readTransferFunction(flags.densityFrom);
    if (flags.dcc) settings.dcc = dccStyleFor(flags, asset);
    settings.assetPath = flags.input;
    ExportResult result;
    {
        ProgressBar bar("exporting", !flags.quiet);
        result = exportAsset(asset, settings, bar.callback());
    }
    const NiftiStorage storage = niftiStorageLike(asset.source, flags.float32);
    const std::vector<WrittenVolume> written = writeVolumeOutputs(
        flags.outputs, openvdb::GridCPtrVec(result.grids.begin(), result.grids.end()), result.lattice.box, storage);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const openvdb::Coord dims = result.lattice.box.dim();
    if (flags.json) {
        nlohmann::json grids = nlohmann::json::array();
        for (const auto& grid : result.grids) grids.push_back(toJson(summarizeGrid(*grid)));
        const nlohmann::json report{{"outputs", toJson(written, storage)},
                                    {"dims", {dims.x(), dims.y(), dims.z()}},
                                    {"threshold", bounded ? nlohmann::json() : nlohmann::json(result.threshold)},
                                    {"max_error", bounded ? nlohmann::json(asset.residual->bound) : nlohmann::json()},
                                    {"seconds", seconds},
                                    {"grids", grids}};
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    printWritten(written, storage);
    std::cout << "in " << seconds << " s: " << dims.x() << "x" << dims.y() << "x" << dims.z() << " voxels, ";
    if (bounded) {
        std::cout << "each within " << asset.residual->bound << " of the source (the residual layer)\n";
    } else {
        std::cout << "inactive at or below " << result.threshold << "\n";
    }
    for (const auto& grid : result.grids) std::cout << toText(summarizeGrid(*grid));
}

}  // namespace

void addExportCommand(CLI::App& app) {
    auto flags = std::make_shared<ExportFlags>();
    CLI::App* command =
        app.add_subcommand("export",
                           "Evaluate a Gaussian asset at voxel centres and write the reconstruction as OpenVDB "
                           "(Blender, Houdini), in the source's physical units");
    command->add_option("asset", flags->input, "Gaussian asset from gvr fit")->required();
    addVolumeOutputOptions(*command, flags->outputs, flags->float32);
    auto* voxelSize = command->add_option("--voxel-size", flags->voxelSize,
                                          "Voxel size in world mm along each of the source's axes "
                                          "(default: the source grid)");
    auto* resolution = command->add_option("--resolution", flags->resolution, "Voxels along the longest world axis")
                           ->excludes(voxelSize);
    command->add_option("--like", flags->like, "Sample on the grid of this volume (.vdb, or anything ingest reads)")
        ->excludes(voxelSize)
        ->excludes(resolution);
    command->add_option("--threshold", flags->threshold,
                        "Voxels at or below this (physical units; luminance for RGB) stay inactive "
                        "(default: midway between the source's background and its ingest threshold, the "
                        "nearer of the two for values in that gap; else the source's minimum)");
    command->add_option("--show", flags->show,
                        "Export only these structures of an asset fitted with --labels: IDs or names, comma-separated");
    command->add_option("--hide", flags->hide, "Leave these structures out (after --show)");
    command->add_option("--names", flags->names, "Colour grid name: blender (color) or houdini (Cd)")
        ->check(CLI::IsMember({"blender", "houdini"}))
        ->capture_default_str();
    command->add_option("--density-from", flags->densityFrom,
                        "RGB: derive density from this transfer function file (its opacity at the "
                        "luminance) instead of the normalised luminance");
    auto* dcc =
        command->add_flag("--dcc", flags->dcc,
                          "For Blender and Houdini: density 0..1 through the transfer function, colour 0..1, one "
                          "unit a metre (default: physical values in millimetres, as eval compares them)");
    command
        ->add_option("--tf", flags->tf,
                     "With --dcc: transfer function, a preset (ct, ct-bone, mri, rgb) or a JSON file as render "
                     "takes it (default: the preset for the data)")
        ->needs(dcc);
    addLayersOption(*command, flags->layers, "on the source's grid");
    addRemovedFormatOption(*command, flags->removedFormat);
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bars");
    command->callback([flags] { runExport(*flags); });
}

}  // namespace gvr
