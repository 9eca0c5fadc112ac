/// @file ZfpStream.h
/// @brief Dense volumes as zfp streams: the reference lossy codec that gvr's
/// Gaussians are measured against (`gvr baseline --method zfp-*`).
///
/// Format, version 1 (all numbers little-endian):
///
/// | offset  | bytes | field                                                        |
/// |---------|-------|--------------------------------------------------------------|
/// | 0       | 8     | magic "GVRZFP" and two zero bytes                            |
/// | 8       | 4     | format version, uint32 (1)                                   |
/// | 12      | 4     | channels C, uint32 (1 or 3)                                  |
/// | 16      | 12    | samples along i, j, k: 3 x uint32                            |
/// | 28      | 4     | zfp mode, uint32: 2 fixed rate, 4 fixed accuracy (zfp_mode)  |
/// | 32      | 8     | the mode's parameter, float64: bits per value, or tolerance t|
/// | 40      | 8 C   | compressed bytes of each channel, uint64                     |
/// | 40 + 8C |       | each channel's zfp bit stream (no zfp header), channel 0 first |
///
/// Each channel is one 3D float field, i fastest; in accuracy mode its samples are
/// coded times 2^floor(log2 t) / t (see ZfpSettings). The stream holds what decoding
/// needs and nothing else: where the samples sit in the world is the source's.
#pragma once

#include "pipeline/FloatVolume.h"

#include <string>

namespace gvr {

enum class ZfpMode { FixedRate, FixedAccuracy };

struct ZfpSettings {
    ZfpMode mode = ZfpMode::FixedAccuracy;
    /// FixedAccuracy: the largest absolute error of any sample, physical units (> 0),
    /// honoured exactly: zfp itself rounds it down to a power of two, so the samples
    /// are coded scaled by that power over the tolerance. FixedRate: compressed bits per value
    /// (per channel sample, > 0); zfp rounds it to whole bits per 4^3 block and
    /// spends at least 9 bits on a block.
    double parameter = 1.0;
};

/// The stream file's bytes for @a volume (1 or 3 channels, values finite).
/// @param effectiveParameter  if given, receives the parameter as zfp applies it
std::string encodeZfp(const FloatVolume& volume, const ZfpSettings& settings, double* effectiveParameter = nullptr);

/// Writes @a stream (from encodeZfp) to @a path atomically.
/// @throw InputError naming @a path when the write fails.
void writeZfpFile(const std::string& path, const std::string& stream);

/// Reads and decodes a stream file. The result has the stream's dims and channels,
/// an identity worldFromIndex and no foreground.
/// @throw InputError naming @a path for a wrong magic or version, a header that
///        contradicts the file's size, or a payload that does not decode to its length.
FloatVolume readZfpFile(const std::string& path);

}  // namespace gvr
