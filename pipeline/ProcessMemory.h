/// @file ProcessMemory.h
/// @brief This process's memory as the system sees it: its peak, and handing back
/// what the heap keeps but no longer uses.
#pragma once

namespace gvr {

/// Peak resident memory of this process so far, in MiB.
double peakRssMiB();

/// Hands the heap's free memory back to the system (glibc; elsewhere nothing).
/// Call it after freeing arrays as large as the Gaussians: glibc raises its mmap
/// threshold after such frees and then keeps them, so a long fit's memory crept up
/// (docs/benchmarks.md, "A fit's memory").
void releaseFreedMemory();

}  // namespace gvr
