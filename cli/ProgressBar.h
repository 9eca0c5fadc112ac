/// @file ProgressBar.h
/// @brief A one-line progress bar on gvr's stderr, shown only when that is a terminal.
#pragma once

#include "pipeline/Progress.h"

#include <chrono>
#include <string>

namespace gvr {

class ProgressBar {
public:
    /// @param label what is being done ("reading", "building grid")
    explicit ProgressBar(std::string label, bool enabled = true);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// Draws the bar at @a fraction in [0, 1], at most ten times a second, with
    /// @a detail (e.g. "iteration 120, 31.2 dB") after it.
    void update(double fraction, const std::string& detail = "");

    /// A callback for library calls that report progress.
    ProgressFn callback();

private:
    void draw(double fraction, const std::string& detail);

    std::string mLabel;
    bool mEnabled;
    bool mDrawn = false;
    std::chrono::steady_clock::time_point mStart, mLastDraw;
};

}  // namespace gvr
