#include "MemoryBudget.h"

#include "Error.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace gvr {

namespace {

constexpr std::int64_t kMaxDimension = std::int64_t(1) << 30;

std::string gibibytes(long double bytes) {
    std::ostringstream out;
    out.precision(3);
    out << bytes / (1024.0L * 1024.0L * 1024.0L) << " GiB";
    return out.str();
}

}  // namespace

std::uint64_t availableMemoryBytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit) {
        if (key == "MemAvailable:") return kib * 1024;
    }
    return std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGE_SIZE));
}

void checkVolumeFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& dims,
                             int channels, std::size_t bytesPerSample) {
    for (std::int64_t d : dims) {
        if (d < 1 || d > kMaxDimension) {
            throw InputError(file, "dimensions " + std::to_string(dims[0]) + "x" +
                                       std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                                       " are out of range (each must be 1.." +
                                       std::to_string(kMaxDimension) + ")");
        }
    }
    // long double: the product of three 2^30 dimensions overflows 64 bits.
    const long double samples = (long double)dims[0] * dims[1] * dims[2] * channels;
    const long double needed = samples * bytesPerSample + samples * sizeof(float);
    const long double available = availableMemoryBytes();
    if (needed > available) {
        throw InputError(file, "a volume of " + std::to_string(dims[0]) + "x" +
                                   std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                                   " voxels needs " + gibibytes(needed) + " to ingest, but only " +
                                   gibibytes(available) + " is available");
    }
}

}  // namespace gvr
