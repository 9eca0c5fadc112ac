/// @file BaselineCodecs.h
/// @brief The reference codecs that gvr's Gaussians are measured against: zfp
/// (fixed accuracy or fixed rate), OpenVDB with Blosc (lossless, or floats saved
/// as half), and box downsampling with trilinear upsampling.
///
/// Each method writes its stream file, reads that file back, and rebuilds the
/// source from it as a grid that `gvr eval` and `gvr render` take exactly as they
/// take a `gvr export`: the source's lattice, transform, name, value type and
/// metadata, with the voxels at or below the source's threshold inactive.
#pragma once

#include "pipeline/FloatVolume.h"
#include "pipeline/Progress.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <optional>
#include <string>

namespace gvr {

enum class BaselineMethod { ZfpAccuracy, ZfpRate, VdbBlosc, VdbHalf, Downsample };

/// "zfp-accuracy", "zfp-rate", "vdb-blosc", "vdb-half" or "downsample".
/// @throw InputError naming --method for any other name.
BaselineMethod parseBaselineMethod(const std::string& name);
std::string baselineMethodName(BaselineMethod method);

/// How far from --target-bytes a stream may lie, as a fraction of the target.
constexpr double kTargetBytesSlack = 0.05;

struct BaselineSettings {
    BaselineMethod method = BaselineMethod::ZfpAccuracy;
    /// zfp-accuracy: the largest absolute error of any sample, physical units (> 0).
    std::optional<double> tolerance;
    /// zfp-accuracy, instead of a tolerance: the stream size to aim at, in bytes.
    /// The tolerance is bisected (on its logarithm) until the stream lies within
    /// kTargetBytesSlack of it, else the closest stream is kept (matched = false).
    std::optional<std::uint64_t> targetBytes;
    /// zfp-rate: compressed bits per value of one channel, in (0, 64].
    std::optional<double> rate;
    /// downsample: the box averaged into one coarse voxel is factor^3 voxels (>= 2).
    std::optional<int> factor;

    /// Empty when the settings suit the method, else what is wrong, naming the flag.
    std::string validate() const;
};

struct BaselineResult {
    openvdb::GridBase::Ptr reconstruction;
    std::uint64_t streamBytes = 0;
    std::uint64_t voxels = 0;  ///< of the source's volume box
    int channels = 1;
    std::optional<double> tolerance;  ///< zfp-accuracy: as zfp applied it (the one found, for a target)
    std::optional<double> rate;       ///< zfp-rate: as zfp applied it (whole bits per 4^3 block)
    std::optional<int> factor;        ///< downsample
    std::optional<bool> matched;      ///< target search: whether the stream lies within the slack
    /// Encoding and writing the stream (for a search, the final stream only).
    double compressSeconds = 0.0;
    /// Reading and decoding the stream and building the reconstruction.
    double decompressSeconds = 0.0;

    double bitsPerValue() const { return 8.0 * double(streamBytes) / (double(voxels) * channels); }
};

/// Compresses the voxels of volumeBox(@a source) (a float or Vec3s grid) with
/// @a settings.method into @a streamPath, written atomically, then reads that file
/// back and rebuilds the source from it. A source without gvr metadata keeps
/// ingest's default rule (only the reconstruction's minimum is inactive), and its
/// reconstruction starts at index (0, 0, 0) wherever its active box began, at the
/// same place in the world.
/// @throw InputError for invalid settings, a grid of another value type or without
///        voxels, or a stream that fails to decode; the stream file is removed when
///        anything fails after it was written.
BaselineResult runBaseline(const openvdb::GridBase& source, const BaselineSettings& settings,
                           const std::string& streamPath, const ProgressFn& progress = {});

/// @a decoded (the samples of volumeBox(@a source), placed by their
/// worldFromIndex, as a codec gave them back) as a grid that stands in for the
/// source wherever the source is read: its name, class and metadata, with its cut
/// for the inactive voxels, and @a streamPath recorded as the source file. Only
/// the source's metadata is read, so a grid read without its voxels will do.
openvdb::GridBase::Ptr reconstructionOf(const openvdb::GridBase& source, FloatVolume decoded,
                                        const std::string& streamPath, const ProgressFn& progress = {});

}  // namespace gvr
