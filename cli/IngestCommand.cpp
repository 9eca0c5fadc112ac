// gvr ingest INPUT -o OUT.vdb [-o OUT.nii.gz]: any supported volume to a sparse OpenVDB grid (or NIfTI).

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/GridSummary.h"
#include "cli/ProgressBar.h"
#include "cli/SourceOptions.h"
#include "cli/VolumeOutputOptions.h"
#include "io/LabelGrid.h"
#include "io/formats/JsonText.h"
#include "pipeline/Error.h"
#include "pipeline/ProcessMemory.h"
#include "pipeline/VolumeMetadata.h"
#include "workflow/ReportNumbers.h"

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct IngestFlags {
    std::string input;
    std::vector<std::string> outputs;
    std::string labels, labelNames, removedFormat;
    bool resampleLabels = false, float32 = false;
    SourceFlags source;
    bool json = false;
    bool quiet = false;
};

/// Says the warnings in the command line's terms, for stderr and --json alike.
void sayWarnings(std::vector<std::string>& warnings) {
    for (std::string& warning : warnings) {
        warning = inCommandLineTerms(warning);
        diagnostics() << "gvr: warning: " << warning << "\n";
    }
}

/// A label grid has no place in a NIfTI of the image.
void refuseLabelsWithoutVdb(const IngestFlags& flags) {
    if (flags.labels.empty()) return;
    for (const std::string& output : flags.outputs) {
        if (volumeFileFormat(output) == VolumeFileFormat::Vdb) return;
    }
    throw InputError("--labels", "the labels are stored beside the image in a .vdb: add -o OUT.vdb");
}

/// A NIfTI reads as a copy of the source: say so when it holds the thresholded grid
/// instead (a chest CT's 21.7 M voxels of air and padding became -986.5 HU).
void warnOfAThresholdedCopy(const IngestFlags& flags, const openvdb::GridBase& grid,
                            std::vector<std::string>& warnings) {
    const auto metadata = readVolumeMetadata(grid);
    const std::uint64_t dropped = volumeBox(grid).volume() - grid.activeVoxelCount();
    if (!metadata || (!metadata->threshold && !metadata->thresholdAbove) || dropped == 0) return;
    for (const std::string& output : flags.outputs) {
        if (volumeFileFormat(output) == VolumeFileFormat::Vdb) continue;
        std::ostringstream warning;
        warning << output << " holds the ingested grid, not a copy of the source: its " << dropped
                << " voxels outside the threshold hold the grid's background " << metadata->background
                << "; a `threshold` below the data's minimum (" << metadata->valueMin << ") keeps every value";
        warnings.push_back(warning.str());
    }
}

void runIngest(const IngestFlags& flags) {
    rejectRemovedFormat(flags.removedFormat);
    checkVolumeOutputs("-o", flags.outputs, {flags.input, flags.labels, flags.labelNames});
    refuseLabelsWithoutVdb(flags);
    IngestOptions options = toIngestOptions(flags.source);
    options.labels = flags.labels;
    options.labelNames = flags.labelNames;
    options.resampleLabels = flags.resampleLabels;
    IngestResult result;
    const auto start = std::chrono::steady_clock::now();
    {
        ProgressBar reading("reading", !flags.quiet);
        ProgressBar building("building grid", !flags.quiet);
        options.read.progress = reading.callback();
        options.buildProgress = building.callback();
        result = ingest(flags.input, options);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    warnOfAThresholdedCopy(flags, *result.grid, result.warnings);
    sayWarnings(result.warnings);
    if (result.grid->activeVoxelCount() == 0) {
        diagnostics() << "gvr: warning: no voxel is above the threshold; the grid is empty\n";
    }
    openvdb::GridCPtrVec grids{result.grid};
    LabelTable labelTable;
    if (result.labels) {
        labelTable = labelTableOf(*result.labels);
        grids.push_back(result.labels);
    }
    const NiftiStorage storage = ingestedNiftiStorage(*result.grid, flags.float32);
    const std::vector<WrittenVolume> written =
        writeVolumeOutputs(flags.outputs, grids, volumeBox(*result.grid), storage);
    const GridSummary summary = summarizeGrid(*result.grid);
    if (flags.json) {
        nlohmann::json report = {{"outputs", toJson(written, storage)},
                                 {"grid", toJson(summary)},
                                 {"seconds", seconds},
                                 {"peak_rss_mib", peakRssMiB()},
                                 {"warnings", result.warnings}};
        if (!flags.labels.empty()) {
            nlohmann::json names = nlohmann::json::object();
            for (const auto& [id, name] : labelTable.names) names[std::to_string(id)] = name;
            report["labels"] = names;
        }
        std::cout << jsonText(report, 2) << "\n";
    } else {
        printWritten(written, storage);
        std::cout << "in " << std::fixed << std::setprecision(1) << seconds << " s, peak memory "
                  << std::setprecision(0) << peakRssMiB() << " MiB\n"
                  << std::defaultfloat << toText(summary);
        if (!flags.labels.empty()) {
            std::cout << "labels: " << labelTable.names.size() << " structures from " << flags.labels << "\n";
        }
    }
}

}  // namespace

void addIngestCommand(CLI::App& app) {
    auto flags = std::make_shared<IngestFlags>();
    CLI::App* command =
        app.add_subcommand("ingest",
                           "Read a volume (NIfTI, DICOM folder, image stack or multi-page TIFF, raw, MetaImage, "
                           "MGH/MGZ, VDB) into a sparse OpenVDB grid in physical units and world millimetres");
    command
        ->add_option("input", flags->input, "Volume file, DICOM or image folder, or quoted glob such as 'slices/*.png'")
        ->required();
    addVolumeOutputOptions(*command, flags->outputs, flags->float32);
    addRemovedFormatOption(*command, flags->removedFormat);
    addSourceFlags(*command, flags->source);
    command->add_option("--labels", flags->labels,
                        "Integer label volume (atlas or segmentation) on the same grid: stored beside the image "
                        "as an Int32 grid \"labels\" for fit --labels, render --show and eval --labels");
    command->add_option("--label-names", flags->labelNames,
                        "Label names, one \"ID NAME ...\" per line (AAL .txt, FreeSurfer LUT)");
    command->add_flag(
        "--resample-labels", flags->resampleLabels,
        "Resample labels on a different grid onto the image's (nearest neighbour) instead of refusing them");
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bars");
    command->callback([flags] { runIngest(*flags); });
}

}  // namespace gvr
