// gvr export ASSET -o OUT.vdb: the reconstruction as OpenVDB grids (and NIfTI).

#include "AssetExport.h"
#include "AssetFile.h"
#include "AtomicFile.h"
#include "Commands.h"
#include "Error.h"
#include "GridFile.h"
#include "GridSummary.h"
#include "NiftiWriter.h"
#include "ProgressBar.h"
#include "TransferFunctionFile.h"

#include <chrono>
#include <filesystem>
#include <iostream>

namespace gvr {

namespace {

struct ExportFlags {
    std::string input, output, like, names = "blender", densityFrom, format = "vdb", show, hide;
    std::optional<double> voxelSize, threshold;
    std::optional<int> resolution;
    bool json = false, quiet = false;
};

std::optional<Lattice> chosenLattice(const ExportFlags& flags, const GaussianAsset& asset) {
    if (!flags.like.empty()) return latticeLike(flags.like);
    if (flags.resolution) {
        const double voxelSize = voxelSizeForResolution(asset.worldFromIndex, asset.source.dims, *flags.resolution);
        try {
            return resizedLattice(asset.worldFromIndex, asset.source.dims, voxelSize);
        } catch (const InputError&) {  // it names --voxel-size, which this user did not give
            throw InputError("--resolution", std::to_string(*flags.resolution) +
                                                 " voxels along the longest axis would need more than 2^36 voxels");
        }
    }
    if (flags.voxelSize) return resizedLattice(asset.worldFromIndex, asset.source.dims, *flags.voxelSize);
    return std::nullopt;
}

/// OUT.vdb -> OUT.nii.gz beside it.
std::string niftiPathFor(const std::string& output) {
    std::filesystem::path path(output);
    if (path.extension() == ".vdb") path.replace_extension();
    return path.string() + ".nii.gz";
}

void printResult(const ExportFlags& flags, const ExportResult& result, const std::string& niftiPath,
                 double seconds) {
    const std::uint64_t fileBytes = std::filesystem::file_size(flags.output);
    const openvdb::Coord dims = result.lattice.box.dim();
    nlohmann::json grids = nlohmann::json::array();
    for (const auto& grid : result.grids) grids.push_back(toJson(summarizeGrid(*grid)));
    if (flags.json) {
        nlohmann::json out = {{"output", flags.output}, {"file_bytes", fileBytes},
                              {"dims", {dims.x(), dims.y(), dims.z()}}, {"threshold", result.threshold},
                              {"seconds", seconds}, {"grids", grids}};
        if (!niftiPath.empty()) out["nifti"] = niftiPath;
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << "wrote " << flags.output << " (" << formatBytes(fileBytes) << ") in " << seconds << " s: "
              << dims.x() << "x" << dims.y() << "x" << dims.z() << " voxels, inactive at or below "
              << result.threshold << "\n";
    for (const auto& grid : result.grids) std::cout << toText(summarizeGrid(*grid));
    if (!niftiPath.empty()) std::cout << "wrote " << niftiPath << "\n";
}

void runExport(const ExportFlags& flags) {
    checkOutputPath("-o", flags.output, {flags.input, flags.like, flags.densityFrom});
    const auto start = std::chrono::steady_clock::now();
    const GaussianAsset asset = selectStructures(readAsset(flags.input), flags.show, flags.hide, flags.input);
    ExportSettings settings;
    settings.lattice = chosenLattice(flags, asset);
    settings.threshold = flags.threshold;
    settings.naming = flags.names == "houdini" ? GridNaming::Houdini : GridNaming::Blender;
    if (!flags.densityFrom.empty()) settings.densityFrom = readTransferFunction(flags.densityFrom);
    settings.assetPath = flags.input;
    ExportResult result;
    {
        ProgressBar bar("exporting", !flags.quiet);
        result = exportAsset(asset, settings, bar.callback());
    }
    std::string niftiPath;
    if (flags.format == "nifti") {
        niftiPath = niftiPathFor(flags.output);
        const openvdb::GridBase& values = *result.grids.front();
        writeNifti(niftiPath, sampleGrid(values, result.lattice.box));
    }
    try {
        writeGridFile(flags.output, openvdb::GridCPtrVec(result.grids.begin(), result.grids.end()));
    } catch (...) {
        if (!niftiPath.empty()) std::filesystem::remove(niftiPath);
        throw;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    printResult(flags, result, niftiPath, seconds);
}

}  // namespace

void addExportCommand(CLI::App& app) {
    auto flags = std::make_shared<ExportFlags>();
    CLI::App* command = app.add_subcommand(
        "export", "Evaluate a Gaussian asset at voxel centres and write the reconstruction as OpenVDB "
                  "(Blender, Houdini), in the source's physical units");
    command->add_option("asset", flags->input, "Gaussian asset from gvr fit")->required();
    command->add_option("-o,--output", flags->output, "Output .vdb file")->required();
    auto* voxelSize = command->add_option("--voxel-size", flags->voxelSize,
                                          "Voxel size in world mm along each of the source's axes "
                                          "(default: the source grid)");
    auto* resolution = command->add_option("--resolution", flags->resolution,
                                           "Voxels along the longest world axis")->excludes(voxelSize);
    command->add_option("--like", flags->like, "Sample on the grid of this volume (.vdb, or anything ingest reads)")
        ->excludes(voxelSize)->excludes(resolution);
    command->add_option("--threshold", flags->threshold,
                        "Voxels at or below this (physical units; luminance for RGB) stay inactive "
                        "(default: the source's ingest threshold, else its minimum)");
    command->add_option("--show", flags->show,
                        "Export only these structures of an asset fitted with --labels: IDs or names, comma-separated");
    command->add_option("--hide", flags->hide, "Leave these structures out (after --show)");
    command->add_option("--names", flags->names, "Colour grid name: blender (color) or houdini (Cd)")
        ->check(CLI::IsMember({"blender", "houdini"}))->capture_default_str();
    command->add_option("--density-from", flags->densityFrom,
                        "RGB: derive density from this transfer function file (its opacity at the "
                        "luminance) instead of the normalised luminance");
    command->add_option("--format", flags->format, "vdb, or nifti to also write OUT.nii.gz (float32 or RGB24)")
        ->check(CLI::IsMember({"vdb", "nifti"}))->capture_default_str();
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bars");
    command->callback([flags] { runExport(*flags); });
}

}  // namespace gvr
