/// @file MemoryBudget.h
/// @brief Refuses volumes that cannot fit, before anything is allocated from a header.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace gvr {

/// Memory this process may still take: /proc/meminfo's MemAvailable, lowered by
/// the address-space limit (ulimit -v) less what the process maps already, and by
/// setMemoryCeiling().
std::uint64_t availableMemoryBytes();

/// Caps availableMemoryBytes() from now on (0: no cap), for a process that must
/// stay below a limit the kernel does not know about, such as a fuzzer's.
void setMemoryCeiling(std::uint64_t bytes);

/// Each dimension must lie in [1, 2^30] so that it fits OpenVDB's 32-bit coordinates.
/// @throw InputError naming @a file with the dimensions.
void checkDimensions(const std::string& file, const std::array<std::int64_t, 3>& dims);

/// A volume read whole is held as decoded samples and as the float grid built from
/// them at once (export: the float grid and a dense copy); this checks that both
/// fit, and checkDimensions().
/// @param task  what the memory is for, as the message says it ("ingest", "export");
///              for "ingest" the message says which formats stream instead
/// @throw InputError naming @a file with the size that was asked for.
void checkVolumeFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& dims, int channels,
                             std::size_t bytesPerSample, const std::string& task = "ingest");

/// A streamed ingest holds one slab of samples and, at worst, the same voxels
/// again as new grid leaves; this checks that they fit.
/// @param slab     voxels across, down and the slab's slice count
/// @param context  appended to the message (which slices, what helps)
void checkSlabFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& slab, int channels,
                           std::size_t bytesPerSample, const std::string& context = "");

}  // namespace gvr
