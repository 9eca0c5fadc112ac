/// @file MemoryBudget.h
/// @brief Refuses volumes that cannot fit, before anything is allocated from a header.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace gvr {

/// Memory this process may still take, from /proc/meminfo's MemAvailable.
std::uint64_t availableMemoryBytes();

/// Ingest holds the decoded samples and the float grid built from them at once;
/// this checks that both fit. Each dimension must lie in [1, 2^30] so that it
/// fits OpenVDB's 32-bit coordinates.
/// @throw InputError naming @a file with the size that was asked for.
void checkVolumeFitsInMemory(const std::string& file, const std::array<std::int64_t, 3>& dims,
                             int channels, std::size_t bytesPerSample);

}  // namespace gvr
