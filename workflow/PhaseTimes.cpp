#include "workflow/PhaseTimes.h"

#include <iomanip>
#include <sstream>

namespace gvr {

void PhaseTimes::lap(const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    mSteps.emplace_back(name, std::chrono::duration<double>(now - mLast).count());
    mLast = now;
}

nlohmann::json PhaseTimes::json() const {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [name, seconds] : mSteps) out[name] = seconds;
    out["total"] = total();
    return out;
}

std::string PhaseTimes::text() const {
    std::ostringstream out;
    for (const auto& [name, seconds] : mSteps) {
        out << (&name == &mSteps.front().first ? "" : ", ") << name << " " << std::setprecision(4) << seconds << " s";
    }
    out << "; total " << std::setprecision(4) << total() << " s";
    return out.str();
}

double PhaseTimes::total() const {
    double sum = 0.0;
    for (const auto& step : mSteps) sum += step.second;
    return sum;
}

}  // namespace gvr
