/// @file Progress.h
/// @brief How long-running library calls report progress without knowing who listens.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>

namespace gvr {

/// Called with the finished fraction in [0, 1]; may be empty. Calls come from one
/// thread at a time, but not always the caller's.
using ProgressFn = std::function<void(double fraction)>;

/// Counts finished work items from many threads and forwards the fraction done.
class ProgressCounter {
public:
    ProgressCounter(const ProgressFn& report, std::size_t total) : mReport(report), mTotal(total) {}

    /// Reports in order: the count rises under the lock that the report holds.
    void advance() {
        if (!mReport || mTotal == 0) return;
        std::lock_guard<std::mutex> lock(mMutex);
        mReport(double(++mDone) / double(mTotal));
    }

private:
    const ProgressFn& mReport;
    const std::size_t mTotal;
    std::size_t mDone = 0;
    std::mutex mMutex;
};

}  // namespace gvr
