/// @file PhaseTimes.h
/// @brief Wall seconds of each step of a command, in order, for its report.
#pragma once

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace gvr {

class PhaseTimes {
public:
    /// Ends the step that began at the last call (or at construction) as @a name.
    void lap(const std::string& name);

    /// {"load": s, "fit": s, ..., "total": s}
    nlohmann::json json() const;
    /// "load 1.2 s, fit 58.3 s; total 59.5 s"
    std::string text() const;
    double total() const;

private:
    std::chrono::steady_clock::time_point mLast = std::chrono::steady_clock::now();
    std::vector<std::pair<std::string, double>> mSteps;
};

}  // namespace gvr
