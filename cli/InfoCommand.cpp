// gvr info FILE: what a .vdb holds, or what ingest would make of a source volume.

#include "Commands.h"
#include "GridFile.h"
#include "GridSummary.h"
#include "SourceOptions.h"

#include <filesystem>
#include <iostream>

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

void runInfo(const InfoFlags& flags) {
    const bool isGridFile = std::filesystem::is_regular_file(flags.input) && isVdbFile(flags.input);
    std::vector<GridSummary> summaries;
    std::vector<std::string> warnings;
    if (isGridFile) {
        const openvdb::GridPtrVecPtr grids = readGridFile(flags.input);
        for (const auto& grid : *grids) summaries.push_back(summarizeGrid(*grid));
    } else {
        IngestResult result = ingest(flags.input, toIngestOptions(flags.source));
        summaries.push_back(summarizeGrid(*result.grid));
        warnings = std::move(result.warnings);
    }
    const std::uint64_t bytes = sizeOnDisk(flags.input);
    if (flags.json) {
        nlohmann::json report = {{"file", flags.input},
                                 {"kind", isGridFile ? "vdb" : "source"},
                                 {"file_bytes", bytes},
                                 {"grids", nlohmann::json::array()},
                                 {"warnings", warnings}};
        for (const GridSummary& summary : summaries) report["grids"].push_back(toJson(summary));
        std::cout << report.dump(2) << "\n";
        return;
    }
    std::cout << flags.input << ": " << formatBytes(bytes) << " on disk, "
              << (isGridFile ? "OpenVDB file with " + std::to_string(summaries.size()) + " grid(s)"
                             : std::string("source volume; gvr ingest would write:"))
              << "\n";
    for (const std::string& warning : warnings) std::cout << "warning: " << warning << "\n";
    for (const GridSummary& summary : summaries) std::cout << toText(summary);
}

}  // namespace

void addInfoCommand(CLI::App& app) {
    auto flags = std::make_shared<InfoFlags>();
    CLI::App* command = app.add_subcommand(
        "info", "Describe a .vdb file, or show what ingest would make of a source volume "
                "(nothing is written)");
    command->add_option("input", flags->input, "A .vdb file or any volume ingest reads")->required();
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json, "Print the report as JSON");
    command->callback([flags] { runInfo(*flags); });
}

}  // namespace gvr
