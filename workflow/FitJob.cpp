#include "workflow/FitJob.h"

#include "pipeline/Error.h"
#include "workflow/BrickTeam.h"
#include "workflow/ComparisonInput.h"

namespace gvr {

namespace {

void lap(PhaseTimes* phases, const std::string& name) {
    if (phases) phases->lap(name);
}

}  // namespace

FitRequest checkedFitRequest(FitRequest request) {
    checkedSettings(request.options);
    if (request.bound) {
        if (request.bricks.count > 0) throw InputError("`max_error`", "does not combine with `bricks`");
        checkBoundRequest(*request.bound, "`max_error`", "`ratio`");
        request.bound->applyTo(request.options);
    }
    return request;
}

FitJob::FitJob(FitInput input, FitRequest request)
    : mRequest(checkedFitRequest(std::move(request))),
      mInput(std::move(input)),
      mKind(mInput.path.empty() ? FileKind::Other : fileKind(mInput.path)),
      mLoaded(read(mInput, mKind)),
      mTarget(mLoaded.grid, mInput.name()),
      mWarnings(mLoaded.warnings) {
    if (mTarget.activeVoxelCount() == 0) {
        mWarnings.push_back(name() +
                            " has no active voxels (every voxel at or below its threshold), so the asset holds "
                            "no Gaussians");
    }
}

IngestResult FitJob::read(const FitInput& input, FileKind kind) {
    if (input.path.empty()) return input.inMemory;
    if (kind == FileKind::Vdb) return loadGridFile(input.path, input.ingest);
    return ingest(input.path, input.ingest);
}

FloatVolume FitJob::sourceAsRead() const {
    if (mInput.path.empty() || mKind == FileKind::Vdb) return comparisonInputOf(mLoaded.grid, name()).volume;
    IngestOptions options = mInput.ingest;
    options.labels.clear();  // the image's voxels are all the bound needs
    options.labelNames.clear();
    return loadComparisonInput(mInput.path, options).volume;
}

FitOutcome FitJob::run(const FitJobObservers& observers, PhaseTimes* phases) const {
    const BudgetedFitOptions& options = mRequest.options;
    FitOutcome out;
    if (mRequest.bricks.count > 0) {
        out.result =
            fitAllBricks(SoloTeam(), mLoaded.grid, mTarget, name(), options, mRequest.bricks, observers.bricks).result;
    } else {
        out.result = fitToBudget(mTarget, name(), options, observers.fit, mLoaded.labels.get());
    }
    lap(phases, "fit");
    if (mRequest.bound) {
        out.layer.emplace();
        if (observers.layer) observers.layer(0.0);  // the layer's step begins with reading its source
        out.result.file =
            addErrorBound(out.result.file, name(), sourceAsRead(), *mRequest.bound, *out.layer, observers.layer);
        lap(phases, "layer");
    }
    return out;
}

}  // namespace gvr
