#include "io/asset/AssetResidual.h"

#include "io/asset/ResidualCodes.h"
#include "io/asset/ZstdFrame.h"
#include "io/guard/ByteOrder.h"
#include "pipeline/Block.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gvr {

namespace {

constexpr int kZstdLevel = 19;  // the frames are small: a byte per 512 voxels, and the rare exact values
constexpr const char* kCoder = "range-contexts";  // io/asset/ResidualCodes

std::size_t blockCount(const openvdb::Coord& dims) {
    const auto along = [](int n) { return std::size_t((n + kBlockDim - 1) / kBlockDim); };
    return along(dims.x()) * along(dims.y()) * along(dims.z());
}

void appendStreams(std::string& section, const std::vector<std::string>& streams) {
    for (const std::string& stream : streams) {
        appendLittleEndian(section, std::uint64_t(stream.size()));
        section += stream;
    }
}

std::vector<std::string_view> takeStreams(std::string_view section, std::size_t& cursor, std::size_t count) {
    std::vector<std::string_view> streams;
    for (std::size_t n = 0; n < count; ++n) {
        if (section.size() - cursor < sizeof(std::uint64_t)) throw std::runtime_error("residual codes: cut short");
        const auto length = loadLittleEndian<std::uint64_t>(section.data() + cursor);
        cursor += sizeof length;
        if (length > section.size() - cursor)
            throw std::runtime_error("residual codes: a stream runs past the section");
        streams.push_back(section.substr(cursor, length));
        cursor += length;
    }
    return streams;
}

}  // namespace

std::string encodeResidualSection(const ResidualLayer& layer, nlohmann::json& description) {
    std::string predictors(layer.predictors.size(), '\0');
    for (std::size_t b = 0; b < predictors.size(); ++b) predictors[b] = char(layer.predictors[b]);
    std::string exact;
    for (const double value : layer.exact) appendLittleEndian(exact, value);
    std::string section;
    appendZstdFrame(section, predictors, kZstdLevel);
    appendZstdFrame(section, exact, kZstdLevel);
    appendStreams(section, encodeResidualCodes(layer));
    description = {{"bound", layer.bound},
                   {"low", layer.low},
                   {"high", layer.high},
                   {"domain", layer.domain.integers ? "integers" : "values"},
                   {"slope", layer.domain.slope},
                   {"intercept", layer.domain.intercept},
                   {"slab_slices", kResidualSlabSlices},
                   {"coder", kCoder},
                   {"exact_voxels", layer.exact.size()},
                   {"section_bytes", section.size()},
                   {"reconstruction_crc32", layer.reconstructionChecksum}};
    return section;
}

ResidualLayer decodeResidualSection(std::string_view section, const nlohmann::json& description,
                                    const openvdb::Coord& dims, int channels) {
    ResidualLayer layer;
    layer.bound = description.at("bound").get<double>();
    layer.low = description.at("low").get<double>();
    layer.high = description.at("high").get<double>();
    if (!std::isfinite(layer.low) || !std::isfinite(layer.high) || !(layer.low <= layer.high)) {
        throw std::runtime_error("residual: its source range is not a valid range");
    }
    const std::string domain = description.at("domain").get<std::string>();
    if (domain != "integers" && domain != "values") throw std::runtime_error("residual: unknown domain " + domain);
    layer.domain = {domain == "integers", description.at("slope").get<double>(),
                    description.at("intercept").get<double>()};
    if (!(layer.bound >= 0.0) || !std::isfinite(layer.bound) || !(layer.domain.slope != 0.0) ||
        !std::isfinite(layer.domain.slope) || !std::isfinite(layer.domain.intercept)) {
        throw std::runtime_error("residual: its bound or domain is not a valid number");
    }
    if (description.at("slab_slices").get<int>() != kResidualSlabSlices) {
        throw std::runtime_error("residual: slabs of another size than this gvr codes");
    }
    if (description.at("coder").get<std::string>() != kCoder)
        throw std::runtime_error("residual: a coder this gvr does not know");
    layer.dims = dims;
    layer.channels = channels;
    layer.reconstructionChecksum = description.at("reconstruction_crc32").get<std::uint32_t>();
    const std::size_t voxels = std::size_t(dims.x()) * dims.y() * dims.z() * channels;
    const auto exactCount = description.at("exact_voxels").get<std::size_t>();
    if (exactCount > voxels) throw std::runtime_error("residual: more exact values than voxels");
    std::size_t cursor = 0;
    const std::string predictors = takeZstdFrame(section, cursor, blockCount(dims) * channels, "residual predictors");
    const std::string exact = takeZstdFrame(section, cursor, exactCount * sizeof(double), "residual exact values");
    const auto streams = takeStreams(section, cursor, std::size_t(residualSlabCount(dims)));
    if (cursor != section.size()) throw std::runtime_error("residual: bytes after its last stream");
    layer.predictors.resize(predictors.size());
    for (std::size_t b = 0; b < predictors.size(); ++b) {
        if (std::uint8_t(predictors[b]) >= kResidualPredictors) throw std::runtime_error("residual: unknown predictor");
        layer.predictors[b] = ResidualPredictor(predictors[b]);
    }
    layer.codes.assign(voxels, 0);
    decodeResidualCodes(streams, layer);
    if (std::size_t(std::count(layer.codes.begin(), layer.codes.end(), kResidualExact)) != exactCount) {
        throw std::runtime_error("residual: exact voxels do not match their codes");
    }
    layer.exact.resize(exactCount);
    for (std::size_t n = 0; n < exactCount; ++n) {
        layer.exact[n] = loadLittleEndian<double>(exact.data() + n * sizeof(double));
        if (!std::isfinite(layer.exact[n])) throw std::runtime_error("residual: an exact value is not finite");
    }
    return layer;
}

std::uint32_t reconstructionChecksum(const FloatVolume& volume) {
    uLong crc = crc32(0L, Z_NULL, 0);
    const auto* bytes = reinterpret_cast<const Bytef*>(volume.values.data());
    const std::size_t size = volume.values.size() * sizeof(float);
    constexpr std::size_t kChunk = std::size_t(1) << 30;  // crc32 takes a uInt length
    for (std::size_t at = 0; at < size; at += kChunk) crc = crc32(crc, bytes + at, uInt(std::min(kChunk, size - at)));
    return std::uint32_t(crc);
}

}  // namespace gvr
