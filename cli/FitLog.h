/// @file FitLog.h
/// @brief The CSV of a fit's error against run time (`gvr fit --log`).
#pragma once

#include "io/guard/AtomicFile.h"
#include "pipeline/Fitter.h"

#include <fstream>
#include <memory>
#include <string>

namespace gvr {

/// One row per held-out evaluation: a header row and numbers only, so that any CSV
/// reader takes it as it is. Its columns are described in the README; seconds count
/// from the start of the command, reading the input included. Written as the fit
/// goes, so that it can be watched; a fit that fails, or is stopped by a signal,
/// leaves none (see finish()).
class FitLog {
public:
    /// An empty @a path logs nothing. @a secondsBefore: the command's time before the fit.
    /// @throw InputError naming @a path when it cannot be written.
    FitLog(const std::string& path, double secondsBefore);
    FitLog(const FitLog&) = delete;
    FitLog& operator=(const FitLog&) = delete;
    /// Removes the log unless finish() kept it.
    ~FitLog();

    /// Adds a row when @a p carries a held-out evaluation.
    /// @throw InputError naming the log when the disk refuses the row.
    void record(const FitProgress& p);

    /// Keeps the log: the fit and its asset are written.
    /// @throw InputError naming the log when its last rows cannot be written.
    void finish();

private:
    std::string mPath;
    double mSecondsBefore;
    std::ofstream mOut;
    std::unique_ptr<RemovedOnSignal> mUnfinished;  // until finish() keeps it
};

}  // namespace gvr
