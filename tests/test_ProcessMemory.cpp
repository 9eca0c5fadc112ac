// The process's peak memory as the system counts it, and handing freed heap back.

#include "pipeline/ProcessMemory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace gvr {
namespace {

TEST(ProcessMemory, ThePeakCoversMemoryThatWasTouched) {
    const double before = peakRssMiB();
    EXPECT_TRUE(std::isfinite(before));
    EXPECT_GT(before, 0.0);
    // Every page written, through volatile so that the compiler cannot drop the
    // block: untouched pages are never resident.
    std::vector<unsigned char> block(std::size_t(48) << 20);
    volatile unsigned char* page = block.data();
    for (std::size_t n = 0; n < block.size(); n += 4096) page[n] = 1;
    EXPECT_EQ(block[4096], 1);
    const double after = peakRssMiB();
    EXPECT_GE(after, 48.0);
    EXPECT_GE(after, before);  // a peak never falls
}

TEST(ProcessMemory, ReleasingFreedMemoryKeepsTheHeapUsableAndThePeak) {
    double peak = 0.0;
    {
        const std::vector<double> big(std::size_t(4) << 20, 1.0);  // 32 MiB, freed at the brace
        EXPECT_EQ(big.back(), 1.0);
        peak = peakRssMiB();
    }
    releaseFreedMemory();
    releaseFreedMemory();  // nothing left to hand back: harmless
    EXPECT_GE(peakRssMiB(), peak);
    std::vector<int> again(1000, 3);
    EXPECT_EQ(std::accumulate(again.begin(), again.end(), 0), 3000);
}

}  // namespace
}  // namespace gvr
