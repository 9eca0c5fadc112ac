#include "Report.h"

#include <sys/resource.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace gvr {

std::string formatDb(double db) {
    if (std::isinf(db)) return db > 0 ? "inf" : "-inf";
    std::ostringstream out;
    out << std::fixed << std::setprecision(2) << db;
    return out.str();
}

double peakRssMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;
}

}  // namespace gvr
