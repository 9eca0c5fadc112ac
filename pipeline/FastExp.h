/// @file FastExp.h
/// @brief exp over four floats at once, for the renderer's hot loops.
///
/// std::exp is a call per value, which no compiler vectorises without fast-math;
/// this is a degree-6 polynomial on t - n ln 2, scaled by 2^n, written with
/// GCC/Clang vector types so that it compiles to SSE on any x86-64.
#pragma once

#include <cstdint>

namespace gvr {

using Floats4 = float __attribute__((vector_size(16)));
using Ints4 = std::int32_t __attribute__((vector_size(16)));  ///< lane masks: -1 true, 0 false
/// Eight lanes: one AVX register, or two SSE ones where AVX is not enabled. Keep
/// them in locals: their alignment in memory differs with and without AVX.
using Floats8 = float __attribute__((vector_size(32)));

/// exp(t) for t <= 0, within 3e-7 relative; below -87, where float runs out, it is
/// exp(-87) (1.6e-38). Positive t gives wrong values. Any vector of floats: Floats4,
/// or Floats8 in code compiled for AVX.
template <typename Floats>
__attribute__((always_inline)) inline Floats expNonPositive(Floats t) {
    using Ints = decltype(t < t);
    const Floats lowest = Floats{} - 87.0f;
    const Ints inRange = t > lowest;
    t = (Floats)((inRange & (Ints)t) | (~inRange & (Ints)lowest));
    // The nearest integer to t / ln 2: conversion truncates towards zero, and t <= 0.
    const Ints n = __builtin_convertvector(t * 1.44269504f - 0.5f, Ints);
    const Floats nf = __builtin_convertvector(n, Floats);
    // ln 2 in two parts, the first exact in few bits, so that n ln 2 loses nothing (Cody and Waite).
    const Floats r = (t - nf * 0.693359375f) + nf * 2.12194440e-4f;
    const Floats p =
        1.0f + r * (1.0f + r * (0.5f + r * (1.0f / 6 + r * (1.0f / 24 + r * (1.0f / 120 + r * (1.0f / 720))))));
    return p * (Floats)((n + 127) << 23);  // the exponent bits of 2^n
}

/// Whether this processor runs code compiled with __attribute__((target("avx2"))),
/// for the hot loops that dispatch to eight lanes at run time.
inline bool processorHasAvx2() {
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
}

/// Whether it also runs code compiled with target("avx2,fma"): fused multiply-adds
/// halve the exp polynomial's chain of dependent operations.
inline bool processorHasAvx2Fma() {
    static const bool has = processorHasAvx2() && __builtin_cpu_supports("fma");
    return has;
}

}  // namespace gvr
