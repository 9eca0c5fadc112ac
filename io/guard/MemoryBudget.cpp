#include "io/guard/MemoryBudget.h"

#include "pipeline/Error.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <sstream>

namespace gvr {

namespace {

constexpr std::int64_t kMaxDimension = std::int64_t(1) << 30;

std::atomic<std::uint64_t> gCeiling{0};

/// A "Key: N kB" line of a /proc file, in bytes; 0 when it is missing.
std::uint64_t procKibibytes(const char* file, const std::string& wanted) {
    std::ifstream in(file);
    std::string key;
    std::uint64_t kib = 0;
    std::string unit;
    while (in >> key >> kib >> unit) {
        if (key == wanted) return kib * 1024;
    }
    return 0;
}

/// What ulimit -v still leaves, or no limit.
std::uint64_t addressSpaceLeft() {
    rlimit limit{};
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
    const std::uint64_t mapped = procKibibytes("/proc/self/status", "VmSize:");
    return limit.rlim_cur > mapped ? limit.rlim_cur - mapped : 0;
}

std::string gibibytes(long double bytes) {
    std::ostringstream out;
    out.precision(3);
    out << bytes / (1024.0L * 1024.0L * 1024.0L) << " GiB";
    return out.str();
}

}  // namespace

std::uint64_t availableMemoryBytes() {
    std::uint64_t available = procKibibytes("/proc/meminfo", "MemAvailable:");
    if (available == 0) available = std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGE_SIZE));
    available = std::min(available, addressSpaceLeft());
    const std::uint64_t ceiling = gCeiling.load();
    return ceiling > 0 ? std::min(available, ceiling) : available;
}

void setMemoryCeiling(std::uint64_t bytes) { gCeiling.store(bytes); }

void checkDimensions(const std::string& file, const std::array<std::int64_t, 3>& dims) {
    for (std::int64_t d : dims) {
        if (d < 1 || d > kMaxDimension) {
            throw InputError(file, "dimensions " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                                       std::to_string(dims[2]) + " are out of range (each must be 1.." +
                                       std::to_string(kMaxDimension) + ")");
        }
    }
}

void checkVolumeFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& dims, int channels,
                             std::size_t bytesPerSample, const std::string& task) {
    checkDimensions(file, dims);
    // long double: the product of three 2^30 dimensions overflows 64 bits.
    const long double samples = (long double)dims[0] * dims[1] * dims[2] * channels;
    const long double needed = samples * bytesPerSample + samples * sizeof(float);
    const long double available = availableMemoryBytes();
    if (needed > available) {
        const std::string hint = task != "ingest" ? ""
                                                  : "; NIfTI, MGH, MetaImage and VDB volumes are read whole, while raw "
                                                    "files (`raw_dims`), image stacks and DICOM series are streamed "
                                                    "slab by slab and need memory only for their active voxels";
        throw InputError(file, "a volume of " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
                                   std::to_string(dims[2]) + " voxels needs " + gibibytes(needed) + " to " + task +
                                   ", but only " + gibibytes(available) + " is available" + hint);
    }
}

void checkSlabFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& slab, int channels,
                           std::size_t bytesPerSample, const std::string& context) {
    const long double samples = (long double)slab[0] * slab[1] * slab[2] * channels;
    const long double needed = samples * bytesPerSample + samples * sizeof(float);
    const long double available = availableMemoryBytes();
    if (needed > available) {
        throw InputError(file, "one slab of " + std::to_string(slab[2]) + " slices of " + std::to_string(slab[0]) +
                                   "x" + std::to_string(slab[1]) + " voxels needs " + gibibytes(needed) +
                                   " to stream, but only " + gibibytes(available) + " is available" + context);
    }
}

}  // namespace gvr
