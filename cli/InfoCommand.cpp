// gvr info FILE: what a .vdb holds, or what ingest would make of a source volume.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/GridSummary.h"
#include "cli/SourceOptions.h"
#include "io/asset/AssetFile.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/formats/JsonText.h"

#include <filesystem>
#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct InfoFlags {
    std::string input;
    SourceFlags source;
    bool json = false;
};

std::uint64_t sizeOnDisk(const std::string& path) {
    namespace fs = std::filesystem;
    if (fs::is_regular_file(path)) return fs::file_size(path);
    std::uint64_t total = 0;
    if (fs::is_directory(path)) {
        for (const auto& entry : fs::directory_iterator(path)) {
            if (entry.is_regular_file()) total += entry.file_size();
        }
    }
    return total;
}

/// The asset's layers: the Gaussians, and the residual layer of fit --max-error.
nlohmann::json layersJson(const GaussianAsset& asset) {
    nlohmann::json layers = nlohmann::json::array({{{"name", "gaussians"}}});
    if (asset.residual) {
        layers.push_back({{"name", "residual"},
                          {"max_error", asset.residual->bound},
                          {"domain", asset.residual->domain.integers ? "stored samples" : "values"},
                          {"exact_voxels", asset.residual->exactVoxels()}});
    }
    return layers;
}

std::string layersText(const GaussianAsset& asset) {
    if (!asset.residual) return "the Gaussians";
    std::ostringstream text;
    text << "the Gaussians (the preview: export --layers gaussians), and a residual layer: every voxel within "
         << asset.residual->bound << " of the source on its grid (" << asset.residual->exactVoxels()
         << " stored exactly)";
    return text.str();
}

void printAssetInfo(const InfoFlags& flags) {
    const GaussianAsset asset = readAsset(flags.input);
    const std::uint64_t fileBytes = std::filesystem::file_size(flags.input);
    const VolumeMetadata& source = asset.source;
    const std::uint64_t rawBytes = source.rawSourceBytes();
    const std::uint64_t floatBytes =
        std::uint64_t(source.dims.x()) * source.dims.y() * source.dims.z() * source.channels * 4;
    const double vsRaw = double(rawBytes) / double(fileBytes);
    const double vsFloat = double(floatBytes) / double(fileBytes);
    const double perGaussian = double(fileBytes) / double(std::max<std::size_t>(asset.params.count(), 1));
    if (flags.json) {
        const nlohmann::json report = {{"file", flags.input},
                                       {"kind", "gaussian asset"},
                                       {"format_version", asset.formatVersion},
                                       {"gaussians", asset.params.count()},
                                       {"channels", asset.params.channels},
                                       {"cutoff_sigmas", asset.cutoffSigmas},
                                       {"file_bytes", fileBytes},
                                       {"bytes_per_gaussian", perGaussian},
                                       {"raw_source_bytes", rawBytes},
                                       {"ratio_vs_raw", vsRaw},
                                       {"ratio_vs_float32", vsFloat},
                                       {"source_file", source.sourceFile},
                                       {"source_dims", {source.dims.x(), source.dims.y(), source.dims.z()}},
                                       {"fit", asset.fitSettings},
                                       {"layers", layersJson(asset)}};
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    std::cout << flags.input << ": gvr Gaussian asset (format version " << asset.formatVersion << ")\n"
              << "  gaussians:    " << asset.params.count() << " (" << asset.params.channels
              << (asset.params.channels == 1 ? " channel, grey" : " channels, RGB") << ")\n"
              << "  file:         " << formatBytes(fileBytes) << " (" << fileBytes << " bytes, " << perGaussian
              << " per Gaussian, header included)\n"
              << "  compression:  " << vsRaw << ":1 against the raw source (" << formatBytes(rawBytes) << " of "
              << source.sourceType << "), " << vsFloat << ":1 against float32\n"
              << "  source:       " << source.sourceFile << ", " << source.dims.x() << " x " << source.dims.y() << " x "
              << source.dims.z() << " voxels\n"
              << "  cutoff:       " << asset.cutoffSigmas << " standard deviations\n"
              << "  layers:       " << layersText(asset) << "\n"
              << "  fit settings: " << jsonText(asset.fitSettings) << "\n";
}

void runInfo(const InfoFlags& flags) {
    const FileKind kind = fileKind(flags.input);
    if (kind == FileKind::Asset) {
        printAssetInfo(flags);
        return;
    }
    const bool isGridFile = kind == FileKind::Vdb;
    std::vector<GridSummary> summaries;
    std::vector<std::string> warnings;
    if (isGridFile) {
        const openvdb::GridPtrVecPtr grids = readGridFile(flags.input);
        for (const auto& grid : *grids) summaries.push_back(summarizeGrid(*grid));
    } else {
        IngestResult result = ingest(flags.input, toIngestOptions(flags.source));
        summaries.push_back(summarizeGrid(*result.grid));
        for (const std::string& warning : result.warnings) warnings.push_back(inCommandLineTerms(warning));
    }
    const std::uint64_t bytes = sizeOnDisk(flags.input);
    if (flags.json) {
        nlohmann::json report = {{"file", flags.input},
                                 {"kind", isGridFile ? "vdb" : "source"},
                                 {"file_bytes", bytes},
                                 {"grids", nlohmann::json::array()},
                                 {"warnings", warnings}};
        for (const GridSummary& summary : summaries) report["grids"].push_back(toJson(summary));
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    std::cout << flags.input << ": " << formatBytes(bytes) << " on disk, "
              << (isGridFile ? "OpenVDB file with " + std::to_string(summaries.size()) + " grid(s)"
                             : std::string("source volume; gvr ingest would write:"))
              << "\n";
    for (const std::string& warning : warnings) diagnostics() << "gvr: warning: " << warning << "\n";
    for (const GridSummary& summary : summaries) std::cout << toText(summary);
}

}  // namespace

void addInfoCommand(CLI::App& app) {
    auto flags = std::make_shared<InfoFlags>();
    CLI::App* command =
        app.add_subcommand("info",
                           "Describe a .vdb file or a Gaussian asset, or show what ingest would make of a "
                           "source volume (nothing is written)");
    command->add_option("input", flags->input, "A .vdb file, a Gaussian asset, or any volume ingest reads")->required();
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json, "Print the report as JSON");
    command->callback([flags] { runInfo(*flags); });
}

}  // namespace gvr
