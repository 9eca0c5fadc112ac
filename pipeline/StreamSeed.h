/// @file StreamSeed.h
/// @brief Independent random streams from one seed, so that runs are reproducible
/// whatever the thread count.
#pragma once

#include <cstdint>
#include <random>

namespace gvr {

/// A seed for one purpose at one index (an iteration, a chunk of work).
inline std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t purpose, std::uint64_t index) {
    std::seed_seq sequence{std::uint32_t(seed), std::uint32_t(seed >> 32), std::uint32_t(purpose), std::uint32_t(index),
                           std::uint32_t(index >> 32)};
    std::uint32_t words[2];
    sequence.generate(words, words + 2);
    return (std::uint64_t(words[0]) << 32) | words[1];
}

}  // namespace gvr
