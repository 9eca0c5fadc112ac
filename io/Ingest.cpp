#include "Ingest.h"

#include "GridFile.h"

#include <filesystem>

namespace gvr {

IngestResult ingest(const std::string& input, IngestOptions options) {
    initializeOpenVdb();
    DenseVolume volume = readVolume(input, options.read);
    options.build.sourceFile = input;
    IngestResult result;
    result.grid = buildGrid(volume, options.build, options.buildProgress);
    result.warnings = std::move(volume.warnings);
    return result;
}

IngestResult loadOrIngest(const std::string& input, const IngestOptions& options) {
    if (std::filesystem::is_regular_file(input) && isVdbFile(input)) {
        IngestResult result;
        result.grid = chooseVolumeGrid(*readGridFile(input), input);
        return result;
    }
    return ingest(input, options);
}

}  // namespace gvr
