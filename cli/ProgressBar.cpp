#include "cli/ProgressBar.h"

#include "cli/Diagnostics.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

}  // namespace

ProgressBar::ProgressBar(std::string label, bool enabled)
    : mLabel(std::move(label)), mEnabled(enabled && isatty(diagnosticsFd())), mStart(Clock::now()), mLastDraw(mStart) {}

ProgressBar::~ProgressBar() {
    if (mDrawn) std::fputc('\n', diagnosticsFile());
}

void ProgressBar::update(double fraction, const std::string& detail) {
    if (!mEnabled) return;
    const Clock::time_point now = Clock::now();
    if (fraction < 1.0 && mDrawn && secondsBetween(mLastDraw, now) < 0.1) return;
    mLastDraw = now;
    draw(std::clamp(fraction, 0.0, 1.0), detail);
}

ProgressFn ProgressBar::callback() {
    return [this](double fraction) { update(fraction); };
}

void ProgressBar::draw(double fraction, const std::string& detail) {
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth);
    const double elapsed = secondsBetween(mStart, Clock::now());
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(diagnosticsFile(), "\r%-14s [%.*s%*s] %5.1f %%  %6.1f s elapsed, ETA %6.1f s  %s\033[K",
                 mLabel.c_str(), filled, "##############################", kWidth - filled, "", 100.0 * fraction,
                 elapsed, eta, detail.c_str());
    std::fflush(diagnosticsFile());
    mDrawn = true;
}

}  // namespace gvr
