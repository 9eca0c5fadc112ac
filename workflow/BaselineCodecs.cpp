#include "workflow/BaselineCodecs.h"

#include "io/DenseCopy.h"
#include "io/GridBuilder.h"
#include "io/formats/GridFile.h"
#include "pipeline/BoxAverage.h"
#include "pipeline/Error.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/VolumeGrid.h"
#include "pipeline/VolumeMetadata.h"
#include "workflow/ZfpStream.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

constexpr std::pair<BaselineMethod, const char*> kMethodNames[] = {{BaselineMethod::ZfpAccuracy, "zfp-accuracy"},
                                                                   {BaselineMethod::ZfpRate, "zfp-rate"},
                                                                   {BaselineMethod::VdbBlosc, "vdb-blosc"},
                                                                   {BaselineMethod::VdbHalf, "vdb-half"},
                                                                   {BaselineMethod::Downsample, "downsample"}};

/// The largest magnitude a half float holds.
constexpr double kHalfMax = 65504.0;

/// Reports the fraction done of a phase that spans [from, to] of the whole.
ProgressFn phase(const ProgressFn& progress, double from, double to) {
    if (!progress) return {};
    return [=](double fraction) { progress(from + (to - from) * fraction); };
}

float largestMagnitude(const FloatVolume& volume) {
    float largest = 0.0f;
    for (float v : volume.values) largest = std::max(largest, std::abs(v));
    return largest;
}

// The reconstruction ------------------------------------------------------------

/// The value at or below which the source's voxels are inactive, as the exporter reads it.
std::optional<double> sourceCut(const openvdb::GridBase& source) {
    const auto metadata = readVolumeMetadata(source);
    if (!metadata) return std::nullopt;
    return metadata->threshold.value_or(metadata->valueMin);
}

/// buildGrid takes samples as bytes; @a volume is released once they are copied.
DenseVolume denseOf(FloatVolume&& volume) {
    DenseVolume dense;
    dense.dims = {volume.dims.x(), volume.dims.y(), volume.dims.z()};
    dense.channels = volume.channels;
    dense.type = SampleType::Float32;
    dense.worldFromIndex = volume.worldFromIndex;
    dense.samples.resize(volume.values.size() * sizeof(float));
    std::memcpy(dense.samples.data(), volume.values.data(), dense.samples.size());
    volume = FloatVolume();
    return dense;
}

/// A grid of @a samples (placed by their worldFromIndex), built as ingest builds
/// one, with the source's cut for the inactive voxels and @a sourceFile recorded.
openvdb::GridBase::Ptr gridOf(const openvdb::GridBase& source, FloatVolume samples, const std::string& sourceFile,
                              const ProgressFn& progress = {}) {
    GridBuildSettings build;
    build.sourceFile = sourceFile;
    build.threshold = sourceCut(source);
    return buildGrid(denseOf(std::move(samples)), build, progress);
}

// zfp ----------------------------------------------------------------------------

struct Encoded {
    std::string stream;
    double parameter = 0.0;  ///< as zfp applied it
    double seconds = 0.0;
};

Encoded encodeTimed(const FloatVolume& samples, const ZfpSettings& settings) {
    const auto start = Clock::now();
    Encoded encoded;
    encoded.stream = encodeZfp(samples, settings, &encoded.parameter);
    encoded.seconds = secondsSince(start);
    return encoded;
}

/// Bisects the logarithm of the tolerance, since stream size falls smoothly as the
/// tolerance grows. At the top every block collapses: zfp keeps 2 (d + 1) = 8 bit
/// planes beyond the tolerance, so that takes 2^8 times the largest magnitude; 48
/// binary places below that magnitude is past float precision.
/// @return the stream closest to @a target.
Encoded searchTolerance(const FloatVolume& samples, std::uint64_t target, bool& matched, const ProgressFn& progress) {
    int top = 0;  // the largest magnitude is below 2^top
    std::frexp(largestMagnitude(samples), &top);
    double small = top + 8, large = top - 48;  // log2 tolerances of the smallest and the largest stream
    constexpr int kMostAttempts = 40;
    int attempts = 0;
    Encoded best;
    const auto distance = [&](std::size_t bytes) { return std::abs(double(bytes) - double(target)); };
    const auto close = [&] { return distance(best.stream.size()) <= kTargetBytesSlack * double(target); };
    const auto attempt = [&](double log2Tolerance) {
        Encoded encoded = encodeTimed(samples, {ZfpMode::FixedAccuracy, std::exp2(log2Tolerance)});
        const std::size_t bytes = encoded.stream.size();
        if (attempts == 0 || distance(bytes) < distance(best.stream.size())) best = std::move(encoded);
        if (progress) progress(double(++attempts) / kMostAttempts);
        return bytes;
    };
    if (attempt(small) < target && attempt(large) > target) {
        while (attempts < kMostAttempts && !close()) {
            const double middle = 0.5 * (small + large);
            if (attempt(middle) > target)
                large = middle;
            else
                small = middle;
        }
    }
    matched = close();
    return best;
}

void writeZfpStream(const FloatVolume& samples, const BaselineSettings& settings, const std::string& streamPath,
                    BaselineResult& result, const ProgressFn& progress) {
    Encoded encoded;
    if (settings.method == BaselineMethod::ZfpRate) {
        encoded = encodeTimed(samples, {ZfpMode::FixedRate, *settings.rate});
        result.rate = encoded.parameter;
    } else {
        bool matched = false;
        encoded = settings.targetBytes ? searchTolerance(samples, *settings.targetBytes, matched, progress)
                                       : encodeTimed(samples, {ZfpMode::FixedAccuracy, *settings.tolerance});
        result.tolerance = encoded.parameter;
        if (settings.targetBytes) result.matched = matched;
    }
    const auto start = Clock::now();
    writeZfpFile(streamPath, encoded.stream);
    result.compressSeconds = encoded.seconds + secondsSince(start);
}

// OpenVDB ------------------------------------------------------------------------

void writeVdbStream(const openvdb::GridBase& source, const FloatVolume& samples, bool asHalf,
                    const std::string& streamPath, BaselineResult& result) {
    const float largest = largestMagnitude(samples);
    if (asHalf && largest > kHalfMax) {
        throw InputError("grid '" + source.getName() + "'",
                         "holds magnitudes up to " + std::to_string(largest) + ", beyond half precision's 65504");
    }
    const auto start = Clock::now();
    if (asHalf) {
        openvdb::MetaMap metadata(source);
        metadata.insertMeta(openvdb::GridBase::META_SAVE_HALF_FLOAT, openvdb::BoolMetadata(true));
        writeGridFile(streamPath, {source.copyGridReplacingMetadata(metadata)});
    } else {
        writeGridFile(streamPath, {source.copyGrid()});
    }
    result.compressSeconds = secondsSince(start);
}

// Downsampling -------------------------------------------------------------------

/// Coarse voxel (i, j, k) averages the fine voxels from factor * (i, j, k) on,
/// factor^3 of them or fewer at the far edges, and sits where a full box has its
/// centre: at fine index factor * i + (factor - 1) / 2 along each axis.
FloatVolume boxAverage(const FloatVolume& fine, int factor) {
    const openvdb::Coord dims((fine.dims.x() + factor - 1) / factor, (fine.dims.y() + factor - 1) / factor,
                              (fine.dims.z() + factor - 1) / factor);
    FloatVolume coarse(dims, fine.channels);
    openvdb::math::Mat4d fineFromCoarse = openvdb::math::Mat4d::identity();
    fineFromCoarse.setToScale(openvdb::Vec3d(factor));
    fineFromCoarse.setTranslation(openvdb::Vec3d(0.5 * (factor - 1)));
    coarse.worldFromIndex = fineFromCoarse * fine.worldFromIndex;
    forEachBoxAverage(
        dims, openvdb::Coord(factor), fine.dims, fine.channels,
        [&](int x, int y, int z, double* sums) {
            const float* value = fine.at(x, y, z);
            for (int c = 0; c < fine.channels; ++c) sums[c] += value[c];
        },
        [&](int i, int j, int k, const double* means) {
            for (int c = 0; c < fine.channels; ++c) coarse.at(i, j, k)[c] = float(means[c]);
        });
    return coarse;
}

/// The coarse volume is stored as ingest stores a volume: sparse, with the
/// source's cut, so it gains what the source's own .vdb gains from its threshold.
/// It records no path, so that the stream's size does not depend on where it goes.
void writeDownsampledStream(const openvdb::GridBase& source, const FloatVolume& samples, int factor,
                            const std::string& streamPath, BaselineResult& result) {
    // Beyond the longest axis every factor gives one coarse voxel, and its sums would overflow.
    const int longest = std::max({samples.dims.x(), samples.dims.y(), samples.dims.z()});
    if (factor > longest) {
        throw InputError(streamPath, "`factor=" + std::to_string(factor) + "`" +
                                         " exceeds the volume's longest axis (" + std::to_string(longest) + " voxels)");
    }
    const auto start = Clock::now();
    writeGridFile(streamPath, {gridOf(source, boxAverage(samples, factor), "")});
    result.compressSeconds = secondsSince(start);
    result.factor = factor;
}

// Both directions ----------------------------------------------------------------

/// Writes the stream and fills in the method's figures, compressSeconds included.
void writeStream(const openvdb::GridBase& source, const FloatVolume& samples, const BaselineSettings& settings,
                 const std::string& streamPath, BaselineResult& result, const ProgressFn& progress) {
    switch (settings.method) {
        case BaselineMethod::ZfpAccuracy:
        case BaselineMethod::ZfpRate:
            return writeZfpStream(samples, settings, streamPath, result, progress);
        case BaselineMethod::VdbBlosc:
        case BaselineMethod::VdbHalf:
            return writeVdbStream(source, samples, settings.method == BaselineMethod::VdbHalf, streamPath, result);
        case BaselineMethod::Downsample:
            return writeDownsampledStream(source, samples, *settings.factor, streamPath, result);
    }
}

/// The source's samples (dims and placement as in @a samples) as the stream file gives them back.
FloatVolume readStream(const BaselineSettings& settings, const FloatVolume& samples, const openvdb::CoordBBox& box,
                       const std::string& streamPath) {
    switch (settings.method) {
        case BaselineMethod::ZfpAccuracy:
        case BaselineMethod::ZfpRate: {
            FloatVolume decoded = readZfpFile(streamPath);
            decoded.worldFromIndex = samples.worldFromIndex;  // the stream leaves placement to the source
            return decoded;
        }
        case BaselineMethod::VdbBlosc:
        case BaselineMethod::VdbHalf:
            return denseCopy(*chooseVolumeGrid(*readGridFile(streamPath), streamPath), box, streamPath, "decode");
        case BaselineMethod::Downsample: {
            const openvdb::GridBase::Ptr coarse = chooseVolumeGrid(*readGridFile(streamPath), streamPath);
            return resampleTrilinear(denseCopy(*coarse, volumeBox(*coarse), streamPath, "decode"), samples.dims,
                                     samples.worldFromIndex);
        }
    }
    throw std::logic_error("unknown baseline method");
}

}  // namespace

BaselineMethod parseBaselineMethod(const std::string& name) {
    std::string known;
    for (const auto& [method, methodName] : kMethodNames) {
        if (name == methodName) return method;
        known += std::string(known.empty() ? "" : ", ") + methodName;
    }
    throw InputError("`method`", "'" + name + "' is not one of " + known);
}

std::string baselineMethodName(BaselineMethod method) {
    for (const auto& [m, name] : kMethodNames) {
        if (m == method) return name;
    }
    throw std::logic_error("unknown baseline method");
}

std::string BaselineSettings::validate() const {
    const std::string name = baselineMethodName(method);
    if ((tolerance || targetBytes) && method != BaselineMethod::ZfpAccuracy) {
        return "`tolerance` and `target_bytes` apply to zfp-accuracy, not " + name;
    }
    if (rate && method != BaselineMethod::ZfpRate) return "`rate` applies to zfp-rate, not " + name;
    if (factor && method != BaselineMethod::Downsample) return "`factor` applies to downsample, not " + name;
    switch (method) {
        case BaselineMethod::ZfpAccuracy:
            if (tolerance && targetBytes) return "give `tolerance` or `target_bytes`, not both";
            if (!tolerance && !targetBytes) return "zfp-accuracy needs `tolerance=T` or `target_bytes=N`";
            if (tolerance && !(*tolerance > 0.0 && std::isfinite(*tolerance))) {
                return "`tolerance` must be a positive number (physical units)";
            }
            if (targetBytes && *targetBytes == 0) return "`target_bytes` must be positive";
            return {};
        case BaselineMethod::ZfpRate:
            if (!rate) return "zfp-rate needs `rate=BITS`";
            if (!(*rate > 0.0 && *rate <= 64.0)) return "`rate` must be in (0, 64] bits per value";
            return {};
        case BaselineMethod::Downsample:
            if (!factor) return "downsample needs `factor=F`";
            if (*factor < 2) return "`factor` must be an integer of at least 2, got " + std::to_string(*factor);
            return {};
        case BaselineMethod::VdbBlosc:
        case BaselineMethod::VdbHalf:
            return {};
    }
    return {};
}

openvdb::GridBase::Ptr reconstructionOf(const openvdb::GridBase& source, FloatVolume decoded,
                                        const std::string& streamPath, const ProgressFn& progress) {
    openvdb::GridBase::Ptr grid = gridOf(source, std::move(decoded), streamPath, progress);
    grid->setName(source.getName());
    grid->setGridClass(source.getGridClass());
    if (const auto metadata = readVolumeMetadata(source)) {
        grid->removeMeta("gvr_threshold");  // writeVolumeMetadata leaves it when the source has none
        writeVolumeMetadata(*metadata, *grid);
    }
    return grid;
}

BaselineResult runBaseline(const openvdb::GridBase& source, const BaselineSettings& settings,
                           const std::string& streamPath, const ProgressFn& progress) {
    if (const std::string problem = settings.validate(); !problem.empty()) throw InputError("baseline", problem);
    if (!isVolumeGrid(source)) throw InputError("baseline", notAVolumeGrid(source));
    const std::string culprit = "grid '" + source.getName() + "'";
    const openvdb::CoordBBox box = volumeBox(source);
    if (box.empty()) throw InputError(culprit, "has no voxels to compress");
    const FloatVolume samples = denseCopy(source, box, culprit, "compress");
    BaselineResult result;
    result.voxels = samples.voxelCount();
    result.channels = samples.channels;
    writeStream(source, samples, settings, streamPath, result, phase(progress, 0.0, 0.5));
    try {
        result.streamBytes = std::filesystem::file_size(streamPath);
        const auto start = Clock::now();
        result.reconstruction = reconstructionOf(source, readStream(settings, samples, box, streamPath), streamPath,
                                                 phase(progress, 0.5, 1.0));
        result.decompressSeconds = secondsSince(start);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(streamPath, ignored);
        throw;
    }
    return result;
}

}  // namespace gvr
