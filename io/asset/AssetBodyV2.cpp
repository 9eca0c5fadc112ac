#include "io/asset/AssetBodyV2.h"

#include "io/asset/Quantisation.h"
#include "io/asset/ZstdFrame.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/GaussianKernel.h"
#include "pipeline/MortonCode.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gvr {

namespace {

constexpr int kMaxMeanBits = 21;  // three axes interleave into one 63-bit Morton code

/// Integers of one attribute component, with their width in bits.
struct Stream {
    std::vector<std::uint64_t> values;
    int bits = 8;
};

/// Quaternion to "smallest three": the largest component is implied (made positive,
/// since q and -q are the same rotation).
void packQuaternion(const float raw[4], int bits, std::uint64_t& largestOut, std::uint64_t rest[3]) {
    float q[4];
    const float norm = std::sqrt(raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2] + raw[3] * raw[3]);
    for (int k = 0; k < 4; ++k) q[k] = norm > 0.0f ? raw[k] / norm : (k == 0 ? 1.0f : 0.0f);
    int largest = 0;
    for (int k = 1; k < 4; ++k) {
        if (std::abs(q[k]) > std::abs(q[largest])) largest = k;
    }
    const float sign = q[largest] < 0.0f ? -1.0f : 1.0f;
    largestOut = std::uint64_t(largest);
    int slot = 0;
    for (int k = 0; k < 4; ++k) {
        if (k != largest) rest[slot++] = quantise(sign * q[k], -float(M_SQRT1_2), float(M_SQRT1_2), bits);
    }
}

void unpackQuaternion(std::uint64_t largest, const std::uint64_t rest[3], int bits, float q[4]) {
    int slot = 0;
    for (int k = 0; k < 4; ++k) {
        if (k != int(largest))
            q[k] = dequantise(std::uint32_t(rest[slot++]), -float(M_SQRT1_2), float(M_SQRT1_2), bits);
    }
    completeQuaternion(int(largest), q);
}

void appendPlanes(const Stream& stream, int level, std::string& body) {
    const std::size_t n = stream.values.size();
    std::string plane(n, '\0');
    for (int shift = 0; shift < stream.bits; shift += 8) {
        for (std::size_t i = 0; i < n; ++i) plane[i] = char((stream.values[i] >> shift) & 0xff);
        appendZstdFrame(body, plane, level);
    }
}

/// Reads one stream's planes from @a body at @a cursor, checking every length.
void readPlanes(std::string_view body, std::size_t& cursor, std::size_t count, Stream& stream) {
    stream.values.assign(count, 0);
    for (int shift = 0; shift < stream.bits; shift += 8) {
        const std::string plane = takeZstdFrame(body, cursor, count, "a plane of one byte per Gaussian");
        for (std::size_t i = 0; i < count; ++i) stream.values[i] |= std::uint64_t(std::uint8_t(plane[i])) << shift;
    }
}

/// The streams of the body, in file order, sized for @a count Gaussians.
/// Where each attribute's streams stand in the body, in this order.
enum StreamIndex : std::size_t {
    kPositionStream = 0,      ///< Morton code steps
    kLargestComponentStream,  ///< which quaternion component was left out
    kRotationStreams,         ///< the other three, one stream each
    kLogScaleStreams = kRotationStreams + 3,
    kAmplitudeStreams = kLogScaleStreams + 3,  ///< one per channel
};

std::vector<Stream> emptyStreams(const QuantisationV2& q, std::size_t count) {
    const AssetEncoding& e = q.encoding;
    std::vector<Stream> streams;
    streams.push_back({{}, 3 * q.meanBits});
    streams.push_back({{}, 2});
    for (int k = 0; k < 3; ++k) streams.push_back({{}, e.rotationBits});
    for (int a = 0; a < 3; ++a) streams.push_back({{}, e.logScaleBits});
    for (int c = 0; c < q.channels; ++c) streams.push_back({{}, e.amplitudeBits});
    for (Stream& s : streams) s.values.resize(count);
    return streams;
}

void checkBits(int bits, int lo, int hi, const char* what) {
    if (bits < lo || bits > hi) {
        throw std::runtime_error(std::string(what) + " must be " + std::to_string(lo) + " to " + std::to_string(hi));
    }
}

void checkEncoding(const AssetEncoding& e) {
    if (!(e.meanStep > 0.0f) || !std::isfinite(e.meanStep)) throw std::runtime_error("mean_step must be positive");
    checkBits(e.rotationBits, 2, 15, "rotation_bits");
    checkBits(e.logScaleBits, 2, 16, "log_scale_bits");
    checkBits(e.amplitudeBits, 2, 16, "amplitude_bits");
}

}  // namespace

QuantisationV2::QuantisationV2(const GaussianParameters& params, const AssetEncoding& chosen)
    : encoding(chosen), channels(params.channels) {
    checkEncoding(encoding);
    std::array<float, 3> meanMax{};
    const auto span = [&](auto value, int component, float& lo, float& hi) {
        lo = INFINITY;
        hi = -INFINITY;
        for (std::size_t i = 0; i < params.count(); ++i) {
            lo = std::min(lo, value(i, component));
            hi = std::max(hi, value(i, component));
        }
        if (params.count() == 0) lo = hi = 0.0f;
    };
    const auto mean = [&](std::size_t i, int a) { return params.at(kMeans, i)[a]; };
    const auto logScale = [&](std::size_t i, int a) { return params.at(kLogScales, i)[a]; };
    const auto amplitude = [&](std::size_t i, int c) {
        return sigmoid(*params.at(kOpacityLogits, i)) * params.at(kColours, i)[c];
    };
    float widest = 0.0f;
    for (int a = 0; a < 3; ++a) {
        span(mean, a, meanMin[a], meanMax[a]);
        span(logScale, a, logScaleMin[a], logScaleMax[a]);
        widest = std::max(widest, meanMax[a] - meanMin[a]);
    }
    for (int c = 0; c < channels; ++c) span(amplitude, c, amplitudeMin[c], amplitudeMax[c]);
    // A volume too large for 21 bits per axis at this step gets a coarser step.
    encoding.meanStep = std::max(encoding.meanStep, widest / float((1u << kMaxMeanBits) - 2u));
    const double cells = std::ceil(double(widest) / encoding.meanStep) + 1.0;
    meanBits = std::max(1, int(std::ceil(std::log2(cells + 1.0))));
}

QuantisationV2::QuantisationV2(const nlohmann::json& j, int channelCount) : channels(channelCount) {
    encoding.meanStep = j.at("mean_step").get<float>();
    encoding.rotationBits = j.at("rotation_bits").get<int>();
    encoding.logScaleBits = j.at("log_scale_bits").get<int>();
    encoding.amplitudeBits = j.at("amplitude_bits").get<int>();
    checkEncoding(encoding);
    meanBits = j.at("mean_bits").get<int>();
    checkBits(meanBits, 1, kMaxMeanBits, "mean_bits");
    meanMin = j.at("mean_min").get<std::array<float, 3>>();
    logScaleMin = j.at("log_scale_min").get<std::array<float, 3>>();
    logScaleMax = j.at("log_scale_max").get<std::array<float, 3>>();
    const auto lo = j.at("amplitude_min").get<std::vector<float>>();
    const auto hi = j.at("amplitude_max").get<std::vector<float>>();
    if (int(lo.size()) != channels || int(hi.size()) != channels) {
        throw std::runtime_error("amplitude ranges do not match the channel count");
    }
    std::copy(lo.begin(), lo.end(), amplitudeMin.begin());
    std::copy(hi.begin(), hi.end(), amplitudeMax.begin());
}

nlohmann::json QuantisationV2::json() const {
    return {{"mean_step", encoding.meanStep},
            {"mean_bits", meanBits},
            {"rotation_bits", encoding.rotationBits},
            {"log_scale_bits", encoding.logScaleBits},
            {"amplitude_bits", encoding.amplitudeBits},
            {"mean_min", meanMin},
            {"log_scale_min", logScaleMin},
            {"log_scale_max", logScaleMax},
            {"amplitude_min", std::vector<float>(amplitudeMin.begin(), amplitudeMin.begin() + channels)},
            {"amplitude_max", std::vector<float>(amplitudeMax.begin(), amplitudeMax.begin() + channels)}};
}

std::uint64_t QuantisationV2::mortonCode(const float mean[3]) const {
    const std::uint64_t top = (std::uint64_t(1) << meanBits) - 1;
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
        const double cell = std::round((double(mean[a]) - meanMin[a]) / encoding.meanStep);
        code |= spreadBits(std::uint64_t(std::clamp(cell, 0.0, double(top)))) << a;
    }
    return code;
}

double estimatedBytesPerGaussian(const AssetEncoding& e, int channels, double voxels, double count) {
    const double cells = std::max(voxels, 1.0) / (double(e.meanStep) * e.meanStep * e.meanStep);
    const double positionBits = std::max(std::log2(cells / std::max(count, 1.0)), 0.0) + 2.5;
    const double rotationBits = 2.0 + 3.0 * std::max(e.rotationBits - 3.5, 1.0);
    const double scaleBits = 3.0 * std::max(e.logScaleBits - 0.7, 1.0);
    const double amplitudeBits = channels * std::max(e.amplitudeBits - 1.3, 1.0);
    return (positionBits + rotationBits + scaleBits + amplitudeBits) / 8.0;
}

/// The integers the body stores for @a params, one stream per attribute component.
std::vector<Stream> quantiseStreams(const GaussianParameters& params, const QuantisationV2& q) {
    const std::size_t n = params.count();
    std::vector<Stream> streams = emptyStreams(q, n);
    const AssetEncoding& e = q.encoding;
    const std::uint64_t mask = (std::uint64_t(1) << (3 * q.meanBits)) - 1;
    std::uint64_t previous = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t code = q.mortonCode(params.at(kMeans, i));
        streams[kPositionStream].values[i] = (code - previous) & mask;
        previous = code;
        std::uint64_t rest[3];
        packQuaternion(params.at(kRotations, i), e.rotationBits, streams[kLargestComponentStream].values[i], rest);
        for (int k = 0; k < 3; ++k) streams[kRotationStreams + k].values[i] = rest[k];
        for (int a = 0; a < 3; ++a) {
            streams[kLogScaleStreams + a].values[i] =
                quantise(params.at(kLogScales, i)[a], q.logScaleMin[a], q.logScaleMax[a], e.logScaleBits);
        }
        const float opacity = sigmoid(*params.at(kOpacityLogits, i));
        for (int c = 0; c < q.channels; ++c) {
            streams[kAmplitudeStreams + c].values[i] =
                quantise(opacity * params.at(kColours, i)[c], q.amplitudeMin[c], q.amplitudeMax[c], e.amplitudeBits);
        }
    }
    return streams;
}

/// The parameters that @a streams stand for. @throw std::runtime_error for an
/// impossible rotation index.
GaussianParameters dequantiseStreams(const std::vector<Stream>& streams, std::size_t count, const QuantisationV2& q) {
    const AssetEncoding& e = q.encoding;
    const std::uint64_t mask = (std::uint64_t(1) << (3 * q.meanBits)) - 1;
    GaussianParameters params(count, q.channels);
    std::uint64_t code = 0;
    for (std::size_t i = 0; i < count; ++i) {
        code = (code + streams[kPositionStream].values[i]) & mask;
        for (int a = 0; a < 3; ++a) {
            params.at(kMeans, i)[a] = float(q.meanMin[a] + double(compactBits(code >> a)) * e.meanStep);
        }
        const std::uint64_t largest = streams[kLargestComponentStream].values[i];
        if (largest > 3) throw std::runtime_error("a rotation names a fifth quaternion component");
        const std::uint64_t rest[3] = {streams[kRotationStreams].values[i], streams[kRotationStreams + 1].values[i],
                                       streams[kRotationStreams + 2].values[i]};
        unpackQuaternion(largest, rest, e.rotationBits, params.at(kRotations, i));
        for (int a = 0; a < 3; ++a) {
            params.at(kLogScales, i)[a] = dequantise(std::uint32_t(streams[kLogScaleStreams + a].values[i]),
                                                     q.logScaleMin[a], q.logScaleMax[a], e.logScaleBits);
        }
        // Only opacity * colour reaches the field: store it as opacity 1/2 (logit 0).
        *params.at(kOpacityLogits, i) = 0.0f;
        for (int c = 0; c < q.channels; ++c) {
            params.at(kColours, i)[c] = 2.0f * dequantise(std::uint32_t(streams[kAmplitudeStreams + c].values[i]),
                                                          q.amplitudeMin[c], q.amplitudeMax[c], e.amplitudeBits);
        }
    }
    return params;
}

std::string encodeAssetBodyV2(const GaussianParameters& params, const QuantisationV2& q, AttributeBytes* bytes) {
    const std::vector<Stream> streams = quantiseStreams(params, q);
    // zstd at level 19 is most of a write's time, and the fit measures its file's
    // size a few times as it goes: the streams are compressed side by side.
    std::vector<std::string> coded(streams.size());
    tbb::parallel_for(std::size_t(0), streams.size(),
                      [&](std::size_t s) { appendPlanes(streams[s], q.encoding.zstdLevel, coded[s]); });
    std::string body;
    AttributeBytes ignored;
    AttributeBytes& sizes = bytes ? *bytes : ignored;
    for (std::size_t s = 0; s < streams.size(); ++s) {
        body += coded[s];
        std::size_t& attribute = s == kPositionStream    ? sizes.position
                                 : s < kLogScaleStreams  ? sizes.rotation
                                 : s < kAmplitudeStreams ? sizes.logScales
                                                         : sizes.amplitudes;
        attribute += coded[s].size();
    }
    return body;
}

GaussianParameters decodeAssetBodyV2(std::string_view body, std::size_t count, const QuantisationV2& q) {
    std::vector<Stream> streams = emptyStreams(q, 0);
    std::size_t cursor = 0;
    for (Stream& stream : streams) readPlanes(body, cursor, count, stream);
    if (cursor != body.size()) throw std::runtime_error("the body has bytes after its last plane");
    return dequantiseStreams(streams, count, q);
}

GaussianParameters roundTripAssetBodyV2(const GaussianParameters& params, const QuantisationV2& q) {
    return dequantiseStreams(quantiseStreams(params, q), params.count(), q);
}

}  // namespace gvr
