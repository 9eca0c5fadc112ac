#include "io/AssetResidual.h"

#include "io/ByteOrder.h"
#include "io/ZstdFrame.h"
#include "pipeline/Block.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace gvr {

namespace {

constexpr int kZstdLevel = 9;  // seconds on the chest's 67 M voxels, where 19 took minutes
constexpr std::uint32_t kLargestByteCode = 252;
constexpr std::uint8_t kExactByte = 253, kWide16Byte = 254, kWide32Byte = 255;

std::uint32_t zigzag(std::int32_t q) { return (std::uint32_t(q) << 1) ^ std::uint32_t(q >> 31); }
std::int32_t unzigzag(std::uint32_t z) { return std::int32_t(z >> 1) ^ -std::int32_t(z & 1); }

std::size_t blockCount(const openvdb::Coord& dims) {
    const auto along = [](int n) { return std::size_t((n + kBlockDim - 1) / kBlockDim); };
    return along(dims.x()) * along(dims.y()) * along(dims.z());
}

void splitCodes(const ResidualLayer& layer, std::string& bytes, std::string& wide) {
    const std::size_t voxels = layer.codes.size() / layer.channels;
    bytes.resize(layer.codes.size());
    std::size_t n = 0;
    for (int c = 0; c < layer.channels; ++c) {
        for (std::size_t v = 0; v < voxels; ++v) {
            const std::int32_t q = layer.codes[v * layer.channels + c];
            const std::uint32_t z = zigzag(q);
            if (q == kResidualExact) {
                bytes[n++] = char(kExactByte);
            } else if (z <= kLargestByteCode) {
                bytes[n++] = char(z);
            } else if (z <= 0xffff) {
                bytes[n++] = char(kWide16Byte);
                appendLittleEndian(wide, std::uint16_t(z));
            } else {
                bytes[n++] = char(kWide32Byte);
                appendLittleEndian(wide, z);
            }
        }
    }
}

std::vector<std::int32_t> joinCodes(const std::string& bytes, const std::string& wide, int channels,
                                    std::size_t& exactCount) {
    const std::size_t voxels = bytes.size() / channels;
    std::vector<std::int32_t> codes(bytes.size());
    std::size_t n = 0, w = 0;
    exactCount = 0;
    for (int c = 0; c < channels; ++c) {
        for (std::size_t v = 0; v < voxels; ++v) {
            const auto b = std::uint8_t(bytes[n++]);
            std::int32_t& code = codes[v * channels + c];
            if (b == kExactByte) {
                code = kResidualExact;
                ++exactCount;
            } else if (b <= kLargestByteCode) {
                code = unzigzag(b);
            } else {
                const std::size_t width = b == kWide16Byte ? 2 : 4;
                if (wide.size() - w < width) throw std::runtime_error("residual codes: the wide codes run out");
                code = unzigzag(width == 2 ? loadLittleEndian<std::uint16_t>(wide.data() + w)
                                           : loadLittleEndian<std::uint32_t>(wide.data() + w));
                w += width;
                if (!(std::abs(std::int64_t(code)) <= kMaxResidualCode)) {
                    throw std::runtime_error("residual codes: a code beyond the layer's range");
                }
            }
        }
    }
    if (w != wide.size()) throw std::runtime_error("residual codes: wide codes left over");
    return codes;
}

}  // namespace

std::string encodeResidualSection(const ResidualLayer& layer, nlohmann::json& description) {
    std::string predictors(layer.predictors.size(), '\0');
    for (std::size_t b = 0; b < predictors.size(); ++b) predictors[b] = char(layer.predictors[b]);
    std::string bytes, wide;
    splitCodes(layer, bytes, wide);
    std::string exact;
    for (const double value : layer.exact) appendLittleEndian(exact, value);
    std::string section;
    for (const std::string* frame : {&predictors, &bytes, &wide, &exact}) appendZstdFrame(section, *frame, kZstdLevel);
    description = {{"bound", layer.bound},
                   {"domain", layer.domain.integers ? "integers" : "values"},
                   {"slope", layer.domain.slope},
                   {"intercept", layer.domain.intercept},
                   {"slab_slices", kResidualSlabSlices},
                   {"exact_voxels", layer.exact.size()},
                   {"wide_bytes", wide.size()},
                   {"section_bytes", section.size()},
                   {"reconstruction_crc32", layer.reconstructionChecksum}};
    return section;
}

ResidualLayer decodeResidualSection(std::string_view section, const nlohmann::json& description,
                                    const openvdb::Coord& dims, int channels) {
    ResidualLayer layer;
    layer.bound = description.at("bound").get<double>();
    const std::string domain = description.at("domain").get<std::string>();
    if (domain != "integers" && domain != "values") throw std::runtime_error("residual: unknown domain " + domain);
    layer.domain = {domain == "integers", description.at("slope").get<double>(), description.at("intercept").get<double>()};
    if (!(layer.bound >= 0.0) || !std::isfinite(layer.bound) || !(layer.domain.slope != 0.0) ||
        !std::isfinite(layer.domain.slope) || !std::isfinite(layer.domain.intercept)) {
        throw std::runtime_error("residual: its bound or domain is not a valid number");
    }
    if (description.at("slab_slices").get<int>() != kResidualSlabSlices) {
        throw std::runtime_error("residual: slabs of another size than this gvr codes");
    }
    layer.dims = dims;
    layer.channels = channels;
    layer.reconstructionChecksum = description.at("reconstruction_crc32").get<std::uint32_t>();
    const std::size_t voxels = std::size_t(dims.x()) * dims.y() * dims.z() * channels;
    const auto exactCount = description.at("exact_voxels").get<std::size_t>();
    const auto wideBytes = description.at("wide_bytes").get<std::size_t>();
    if (exactCount > voxels || wideBytes > 4 * voxels) throw std::runtime_error("residual: more codes than voxels");
    std::size_t cursor = 0;
    const std::string predictors = takeZstdFrame(section, cursor, blockCount(dims) * channels, "residual predictors");
    const std::string bytes = takeZstdFrame(section, cursor, voxels, "residual codes");
    const std::string wide = takeZstdFrame(section, cursor, wideBytes, "residual wide codes");
    const std::string exact = takeZstdFrame(section, cursor, exactCount * sizeof(double), "residual exact values");
    if (cursor != section.size()) throw std::runtime_error("residual: bytes after its last frame");
    layer.predictors.resize(predictors.size());
    for (std::size_t b = 0; b < predictors.size(); ++b) {
        if (std::uint8_t(predictors[b]) >= kResidualPredictors) throw std::runtime_error("residual: unknown predictor");
        layer.predictors[b] = ResidualPredictor(predictors[b]);
    }
    std::size_t exactCodes = 0;
    layer.codes = joinCodes(bytes, wide, channels, exactCodes);
    if (exactCodes != exactCount) throw std::runtime_error("residual: exact voxels do not match their codes");
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
