#include "Ingest.h"

#include "GridFile.h"

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

}  // namespace gvr
