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

/// Ingest holds the decoded samples and the float grid built from them at once,
/// export the float grid and a dense copy; this checks that both fit. Each
/// dimension must lie in [1, 2^30] so that it fits OpenVDB's 32-bit coordinates.
/// @param task  what the memory is for, as the message says it ("ingest", "export")
/// @throw InputError naming @a file with the size that was asked for.
void checkVolumeFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& dims,
                             int channels, std::size_t bytesPerSample, const std::string& task = "ingest");

}  // namespace gvr
