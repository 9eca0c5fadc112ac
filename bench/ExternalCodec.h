/// @file ExternalCodec.h
/// @brief A compressor outside gvr (SZ3, SPERR, ...) run as a benchmark baseline:
/// two command templates over raw float32 files, with the codec's quality
/// parameter searched until the compressed bytes match a target.
///
/// The raw files hold one channel each, as 32-bit floats in the machine's byte order (little-endian on x86 and ARM) in the
/// volume's own physical units (Hounsfield units stay Hounsfield units), x fastest:
/// C order data[nz][ny][nx], which is what SZ3's `-3 nx ny nz` and sperr3d's
/// `NX NY NZ` mean. An error bound given to the codec is therefore in those units
/// (SZ3's REL bound is a fraction of the channel's value range).
///
/// Placeholders, each standing for one whole argument:
///   {input}       the raw channel to compress
///   {compressed}  the compressed file (written by compress, read by decompress)
///   {output}      the raw channel decompress writes
///   {nx} {ny} {nz}  the dimensions, nx the fastest-varying axis
///   {param}       the quality parameter being searched
#pragma once

#include "pipeline/FloatVolume.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace gvr {

struct ExternalCodec {
    std::string name;                               ///< the method name in manifests and reports
    std::vector<std::string> compress, decompress;  ///< argument vectors with placeholders; no shell
    /// The parameter's search range (both > 0; searched on its logarithm). The
    /// compressed size must change monotonically across it, in either direction.
    double paramMin = 0, paramMax = 0;
    std::string version;  ///< as the manifest gives it, or the first line of versionCommand's output
    std::vector<std::string> versionCommand;
    /// For a whole row: every compress run of the search and the decompression.
    double timeoutSeconds = 600;
};

/// What a codec run failed on; the benchmark makes it the row's message.
struct CodecFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The first placeholder in @a templateArgs that is not one of the above, or "".
std::string unknownPlaceholder(const std::vector<std::string>& templateArgs);

/// The absolute path of @a program: as given when it holds a '/', else the first
/// executable of that name on PATH; "" when there is none.
std::string findProgram(const std::string& program);

/// One volume's channels as raw files (see above), written once and shared by every codec.
struct RawChannels {
    openvdb::Coord dims{0, 0, 0};
    std::vector<std::string> files;  ///< one per channel
    std::uint64_t voxels() const { return std::uint64_t(dims.x()) * dims.y() * dims.z(); }
};

/// Writes the channels of @a volume into @a folder as channel0.f32, ... (each
/// atomically), for every codec of the run to read.
RawChannels writeRawChannels(const FloatVolume& volume, const std::string& folder);

struct CodecResult {
    std::uint64_t bytes = 0;                                            ///< every channel's compressed file, added
    double param = 0;                                                   ///< the parameter that gave them
    bool matched = false;                                               ///< within kTargetBytesSlack of the target
    double compressSeconds = 0, decompressSeconds = 0, peakRssMiB = 0;  ///< of the kept run
    std::vector<float> values;  ///< decompressed, channels interleaved as FloatVolume holds them
};

/// Searches the parameter for compressed files within kTargetBytesSlack of
/// @a targetBytes (else keeps the closest), leaves them in @a folder as
/// compressed.cN, decompresses them, and checks what came back: the right size and
/// finite. Progress and the codec's messages go to @a logPath.
/// @throw CodecFailure with a one-line message: an unknown placeholder, a command
///        that fails, runs past its time limit or writes nothing, or output of the
///        wrong size or with non-finite values.
CodecResult runExternalCodec(const ExternalCodec& codec, const RawChannels& raw, std::uint64_t targetBytes,
                             const std::string& folder, const std::string& logPath);

}  // namespace gvr
