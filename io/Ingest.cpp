#include "io/Ingest.h"

#include "io/LabelGrid.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/FiniteValues.h"
#include "pipeline/ThresholdHoles.h"

#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>

namespace gvr {

namespace {

/// Formats that keep their slices apart stream a slab at a time; the rest are
/// decoded whole first.
IngestResult buildImageGrid(const std::string& input, const IngestOptions& options, std::size_t& decodedBytes) {
    IngestResult result;
    if (const auto source = openSliceSource(input, options.read)) {
        result.grid = buildGrid(*source, options.build, options.buildProgress);
        result.warnings = source->layout().warnings;
        return result;
    }
    DenseVolume volume = readVolume(input, options.read);
    decodedBytes = volume.samples.size();
    result.grid = buildGrid(volume, options.build, options.buildProgress);
    result.warnings = std::move(volume.warnings);
    return result;
}

/// A Hounsfield threshold that also deletes the inside of the body (the lungs,
/// at about -890 HU, under the old advice of -500) is worth a warning.
constexpr double kThresholdHolesWarning = 0.10;

std::optional<std::string> lungWarning(const openvdb::GridBase& grid) {
    const std::optional<VolumeMetadata> metadata = readVolumeMetadata(grid);
    if (!metadata || !metadata->threshold || metadata->channels != 1) return std::nullopt;
    const bool hounsfield = metadata->modality == "CT" || metadata->valueMin <= -1000.0;
    if (!hounsfield || *metadata->threshold <= kCtDefaultThreshold) return std::nullopt;
    const double share = enclosedInactiveShare(grid);
    if (share <= kThresholdHolesWarning) return std::nullopt;
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << "the threshold " << *metadata->threshold << " HU leaves "
         << 100.0 * share << " % of the voxels inside the body's outline inactive (lungs are about -890 HU); "
         << "`threshold=" << kCtDefaultThreshold << "` keeps them";
    return text.str();
}

/// Integers that the float grid rounded change a label atlas or a count volume
/// with no error: worth saying how many.
std::optional<std::string> roundingWarning(const openvdb::GridBase& grid) {
    const std::optional<VolumeMetadata> metadata = readVolumeMetadata(grid);
    if (!metadata || metadata->roundedVoxels == 0) return std::nullopt;
    return std::to_string(metadata->roundedVoxels) + " voxels hold " + metadata->sourceType +
           " integers beyond 2^24, which the float32 grid rounds (16777217 becomes 16777216); "
           "their exports differ from the source by the same rounding";
}

}  // namespace

IngestResult ingest(const std::string& input, IngestOptions options) {
    initializeOpenVdb();
    options.build.sourceFile = input;
    std::size_t decodedBytes = 0;
    try {
        IngestResult result = buildImageGrid(input, options, decodedBytes);
        if (const auto warning = lungWarning(*result.grid)) result.warnings.push_back(*warning);
        if (const auto warning = roundingWarning(*result.grid)) result.warnings.push_back(*warning);
        if (!options.labels.empty()) {
            result.labels = readLabels(options, *result.grid);
            if (result.labels->activeVoxelCount() == 0) {
                result.warnings.push_back("the labels of " + options.labels +
                                          " do not overlap the image: no structure has a voxel in it");
            }
        }
        return result;
    } catch (const std::bad_alloc&) {
        // The memory check passed, so the machine changed under us or a library
        // needed more than it said: name the file and the sizes in play.
        std::string problem = "out of memory while ingesting";
        if (decodedBytes > 0) problem += " " + std::to_string(decodedBytes >> 20) + " MiB of decoded samples";
        throw InputError(input, problem + " (" + std::to_string(availableMemoryBytes() >> 20) +
                                    " MiB available now, ulimit -v included)");
    }
}

IngestResult loadGridFile(const std::string& path, const IngestOptions& options) {
    const openvdb::GridPtrVecPtr grids = options.vdbOnDemand ? readGridFileOnDemand(path) : readGridFile(path);
    IngestResult result;
    result.grid = chooseVolumeGrid(*grids, path);
    // Read on demand, the voxels stay unread until used: each brick's target checks its own.
    if (!options.vdbOnDemand) requireFiniteValues(*result.grid, path);
    result.labels = options.labels.empty() ? storedLabelGrid(*grids) : readLabels(options, *result.grid);
    return result;
}

IngestResult loadOrIngest(const std::string& input, const IngestOptions& options) {
    return fileKind(input) == FileKind::Vdb ? loadGridFile(input, options) : ingest(input, options);
}

openvdb::Int32Grid::Ptr readLabels(const IngestOptions& options, const openvdb::GridBase& image) {
    LabelGridSettings settings;
    if (!options.labelNames.empty()) settings.names = readLabelNames(options.labelNames);
    settings.resample = options.resampleLabels;
    ReadOptions read = options.read;
    read.volumeIndex = 0;
    read.progress = {};
    return buildLabelGrid(options.labels, read, image, settings);
}

}  // namespace gvr
