/// @file FitJob.h
/// @brief One fit as `gvr fit` and Python's `gvr.fit` run it: the request checked
/// before anything is read, the input read once, the Gaussians fitted to their
/// budget (whole, by structure, or in bricks in this process) and, under an error
/// bound, the residual layer over the source as read.
///
/// The front ends only convert: flags or arguments into a FitRequest, and the
/// outcome into a report or a Python object. A fit shared by the ranks of an mpirun
/// reads its input through a FitJob too, then runs fitAllBricks() with its team.
#pragma once

#include "io/Ingest.h"
#include "io/formats/FileKind.h"
#include "pipeline/VolumeTarget.h"
#include "workflow/BoundedLayer.h"
#include "workflow/FitToBudget.h"
#include "workflow/PhaseTimes.h"
#include "workflow/TeamFit.h"

#include <optional>
#include <string>
#include <vector>

namespace gvr {

/// What a fit reads: a file, or a grid already in memory.
struct FitInput {
    /// A .vdb, or any source ingest reads (read with @a ingest); empty for @a inMemory.
    std::string path;
    IngestOptions ingest;
    IngestResult inMemory;  ///< a grid (and its labels, or null), when @a path is empty

    /// The path, or "volume" for a grid in memory: what errors and the asset's record name.
    std::string name() const { return path.empty() ? "volume" : path; }
};

struct FitRequest {
    BudgetedFitOptions options;
    std::optional<BoundRequest> bound;          ///< a residual layer bringing every voxel within it
    BrickOptions bricks{0, kDefaultBrickHalo};  ///< count 0: one whole fit
};

/// Where a job reports its progress; each may be empty.
struct FitJobObservers {
    FitObserver fit;        ///< a whole fit's iterations
    BrickObservers bricks;  ///< each brick's, in a bricked fit
    ProgressFn layer;       ///< the residual layer's encoding
};

struct FitOutcome {
    BudgetedFitResult result;                 ///< result.file holds the residual layer under a bound
    std::optional<BoundedLayerReport> layer;  ///< under a bound
};

/// @a request as a job runs it: its settings and bound checked, and the Gaussians'
/// budget under the bound applied. Cheap, and reads nothing.
/// @throw InputError naming `max_error`, `ratio`, `bricks` or "fit settings".
FitRequest checkedFitRequest(FitRequest request);

class FitJob {
public:
    /// Checks @a request (checkedFitRequest()), then reads @a input.
    /// @throw InputError naming the setting at fault, or the input when it cannot be read.
    FitJob(FitInput input, FitRequest request);

    const FitRequest& request() const { return mRequest; }
    std::string name() const { return mInput.name(); }
    const IngestResult& loaded() const { return mLoaded; }
    /// The fit's target over the grid read, for measuring what the fit gives against it.
    const VolumeTarget& target() const { return mTarget; }
    /// Ingest's warnings, and one when the volume holds no active voxel (the asset
    /// will hold no Gaussians, which is rarely what was meant).
    const std::vector<std::string>& warnings() const { return mWarnings; }

    /// The fit, and its residual layer under a bound; laps "fit" (and "layer") on @a phases.
    /// @throw InputError as fitToBudget(), fitAllBricks() and addErrorBound() do.
    FitOutcome run(const FitJobObservers& observers = {}, PhaseTimes* phases = nullptr) const;

private:
    static IngestResult read(const FitInput& input, FileKind kind);
    /// Every voxel of the source as read, which an ingest threshold does not drop:
    /// the bound holds for these. A grid (a .vdb, or one in memory) is its own source.
    FloatVolume sourceAsRead() const;

    FitRequest mRequest;
    FitInput mInput;
    FileKind mKind;
    IngestResult mLoaded;
    VolumeTarget mTarget;
    std::vector<std::string> mWarnings;
};

}  // namespace gvr
