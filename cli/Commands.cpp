#include "cli/Commands.h"

namespace gvr {

void addCommands(CLI::App& app) {
    // The order of a session: bring a volume in, fit it, get it back out, look at it.
    addIngestCommand(app);
    addInfoCommand(app);
    addFitCommand(app);
    addMergeCommand(app);
    addExportCommand(app);
    addEvalCommand(app);
    addProbeCommand(app);
    addRenderCommand(app);
    addViewCommand(app);
    addBaselineCommand(app);
    addBenchCommand(app);
}

}  // namespace gvr
