#include "Ingest.h"

#include "Error.h"
#include "GridFile.h"
#include "MemoryBudget.h"

#include <filesystem>

namespace gvr {

IngestResult ingest(const std::string& input, IngestOptions options) {
    initializeOpenVdb();
    std::size_t decodedBytes = 0;
    try {
        DenseVolume volume = readVolume(input, options.read);
        decodedBytes = volume.samples.size();
        options.build.sourceFile = input;
        IngestResult result;
        result.grid = buildGrid(volume, options.build, options.buildProgress);
        result.warnings = std::move(volume.warnings);
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

IngestResult loadOrIngest(const std::string& input, const IngestOptions& options) {
    if (std::filesystem::is_regular_file(input) && isVdbFile(input)) {
        IngestResult result;
        result.grid = chooseVolumeGrid(*readGridFile(input), input);
        return result;
    }
    return ingest(input, options);
}

}  // namespace gvr
