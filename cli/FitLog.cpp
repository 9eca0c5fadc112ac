#include "cli/FitLog.h"

#include "pipeline/Error.h"
#include "pipeline/ProcessMemory.h"
#include "workflow/ReportNumbers.h"

#include <filesystem>

namespace gvr {

FitLog::FitLog(const std::string& path, double secondsBefore) : mPath(path), mSecondsBefore(secondsBefore) {
    if (path.empty()) return;
    mOut.open(path);
    if (!mOut) throw InputError(path, "cannot write the fit log");
    mUnfinished = std::make_unique<RemovedOnSignal>(path);
    mOut << "iteration,seconds,loss,psnr_db,gaussians,peak_rss_mib,gradient_share\n";
}

FitLog::~FitLog() {
    if (!mOut.is_open()) return;
    mOut.close();
    std::error_code ignored;
    std::filesystem::remove(mPath, ignored);
}

void FitLog::record(const FitProgress& p) {
    if (!mOut.is_open() || !p.heldOutEvaluated) return;
    mOut << p.iteration << "," << mSecondsBefore + p.seconds << "," << p.loss << "," << formatDb(p.heldOutPsnr) << ","
         << p.gaussians << "," << peakRssMiB() << "," << p.gradientShare << "\n"
         << std::flush;
    if (!mOut) throw InputError(mPath, "cannot write the fit log (disk full?)");
}

void FitLog::finish() {
    if (!mOut.is_open()) return;
    mOut.close();
    if (mOut) {
        mUnfinished.reset();
        return;
    }
    std::error_code ignored;
    std::filesystem::remove(mPath, ignored);
    throw InputError(mPath, "cannot write the fit log (disk full?)");
}

}  // namespace gvr
