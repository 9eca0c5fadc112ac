// gvr ingest INPUT -o OUT.vdb: any supported volume to a sparse OpenVDB grid.

#include "Commands.h"
#include "GridFile.h"
#include "GridSummary.h"
#include "ProgressBar.h"
#include "SourceOptions.h"

#include <filesystem>
#include <iostream>

namespace gvr {

namespace {

struct IngestFlags {
    std::string input;
    std::string output;
    SourceFlags source;
    bool json = false;
    bool quiet = false;
};

void printWarnings(const std::vector<std::string>& warnings) {
    for (const std::string& warning : warnings) std::cerr << "gvr: warning: " << warning << "\n";
}

void runIngest(const IngestFlags& flags) {
    IngestOptions options = toIngestOptions(flags.source);
    IngestResult result;
    {
        ProgressBar reading("reading", !flags.quiet);
        ProgressBar building("building grid", !flags.quiet);
        options.read.progress = reading.callback();
        options.buildProgress = building.callback();
        result = ingest(flags.input, options);
    }
    printWarnings(result.warnings);
    if (result.grid->activeVoxelCount() == 0) {
        std::cerr << "gvr: warning: no voxel is above the threshold; the grid is empty\n";
    }
    writeGridFile(flags.output, {result.grid});
    const std::uint64_t fileBytes = std::filesystem::file_size(flags.output);
    const GridSummary summary = summarizeGrid(*result.grid);
    if (flags.json) {
        nlohmann::json report = {{"output", flags.output},
                                 {"file_bytes", fileBytes},
                                 {"grid", toJson(summary)},
                                 {"warnings", result.warnings}};
        std::cout << report.dump(2) << "\n";
    } else {
        std::cout << "wrote " << flags.output << " (" << formatBytes(fileBytes) << ")\n"
                  << toText(summary);
    }
}

}  // namespace

void addIngestCommand(CLI::App& app) {
    auto flags = std::make_shared<IngestFlags>();
    CLI::App* command = app.add_subcommand(
        "ingest",
        "Read a volume (NIfTI, DICOM folder, image stack or multi-page TIFF, raw, MetaImage, "
        "MGH/MGZ, VDB) into a sparse OpenVDB grid in physical units and world millimetres");
    command->add_option("input", flags->input,
                        "Volume file, DICOM or image folder, or quoted glob such as 'slices/*.png'")
        ->required();
    command->add_option("-o,--output", flags->output, "Output .vdb file")->required();
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bars");
    command->callback([flags] { runIngest(*flags); });
}

}  // namespace gvr
