#include "GaussianAsset.h"

#include "AtomicFile.h"
#include "Error.h"
#include "GaussianKernel.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>
#include <set>

namespace gvr {

namespace {

constexpr char kMagic[8] = {'G', 'V', 'R', 'A', 'S', 'S', 'E', 'T'};
constexpr std::size_t kPreambleBytes = 16;
constexpr std::size_t kChecksumBytes = 4;
constexpr std::size_t kMaxGaussians = std::size_t(1) << 31;

/// Per-channel ranges that the linear quantisers map onto their integers.
struct QuantisationRanges {
    std::array<float, 3> meanMin{}, meanMax{}, logScaleMin{}, logScaleMax{};
    std::array<float, 3> colourMin{}, colourMax{};
};

QuantisationRanges rangesOf(const GaussianParameters& params) {
    QuantisationRanges r;
    const auto span = [&](ParameterGroup group, int component, float& lo, float& hi) {
        lo = INFINITY;
        hi = -INFINITY;
        for (std::size_t i = 0; i < params.count(); ++i) {
            lo = std::min(lo, params.at(group, i)[component]);
            hi = std::max(hi, params.at(group, i)[component]);
        }
        if (params.count() == 0) lo = hi = 0.0f;
    };
    for (int a = 0; a < 3; ++a) {
        span(kMeans, a, r.meanMin[a], r.meanMax[a]);
        span(kLogScales, a, r.logScaleMin[a], r.logScaleMax[a]);
    }
    for (int c = 0; c < params.channels; ++c) span(kColours, c, r.colourMin[c], r.colourMax[c]);
    return r;
}

std::uint16_t quantise16(float value, float lo, float hi) {
    if (!(hi > lo)) return 0;
    const double t = (double(value) - lo) / (double(hi) - lo);
    return std::uint16_t(std::lround(std::clamp(t, 0.0, 1.0) * 65535.0));
}

float dequantise16(std::uint16_t q, float lo, float hi) {
    return float(lo + (double(hi) - lo) * (q / 65535.0));
}

/// Unit quaternion to 32 bits: the largest component is implied (made positive,
/// since q and -q are the same rotation), the other three take 10 bits each.
std::uint32_t packQuaternion(const float raw[4]) {
    float q[4];
    const float norm = std::sqrt(raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2] + raw[3] * raw[3]);
    for (int k = 0; k < 4; ++k) q[k] = norm > 0.0f ? raw[k] / norm : (k == 0 ? 1.0f : 0.0f);
    int largest = 0;
    for (int k = 1; k < 4; ++k) {
        if (std::abs(q[k]) > std::abs(q[largest])) largest = k;
    }
    const float sign = q[largest] < 0.0f ? -1.0f : 1.0f;
    std::uint32_t packed = std::uint32_t(largest) << 30;
    int shift = 20;
    for (int k = 0; k < 4; ++k) {
        if (k == largest) continue;
        const double t = (sign * q[k] * M_SQRT2 + 1.0) * 0.5;  // [-1/sqrt2, 1/sqrt2] -> [0, 1]
        packed |= std::uint32_t(std::lround(std::clamp(t, 0.0, 1.0) * 1023.0)) << shift;
        shift -= 10;
    }
    return packed;
}

void unpackQuaternion(std::uint32_t packed, float q[4]) {
    const int largest = int(packed >> 30);
    int shift = 20;
    float sumSquares = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (k == largest) continue;
        const float t = float((packed >> shift) & 1023u) / 1023.0f;
        q[k] = float((2.0 * t - 1.0) / M_SQRT2);
        sumSquares += q[k] * q[k];
        shift -= 10;
    }
    q[largest] = std::sqrt(std::max(0.0f, 1.0f - sumSquares));
}

std::uint8_t quantiseOpacity(float logit) {
    return std::uint8_t(std::clamp(std::floor(sigmoid(logit) * 256.0f), 0.0f, 255.0f));
}

float opacityOf(std::uint8_t q) { return (q + 0.5f) / 256.0f; }

template <typename T>
void append(std::string& bytes, T value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
}

template <typename T>
T take(const unsigned char*& cursor) {
    T value;
    std::memcpy(&value, cursor, sizeof value);
    cursor += sizeof value;
    return value;
}

std::string encodeBody(const GaussianParameters& params, const QuantisationRanges& r) {
    const std::size_t n = params.count();
    std::string bytes;
    bytes.reserve(n * assetBytesPerGaussian(params.channels));
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) append(bytes, quantise16(params.at(kMeans, i)[a], r.meanMin[a], r.meanMax[a]));
    }
    for (std::size_t i = 0; i < n; ++i) append(bytes, packQuaternion(params.at(kRotations, i)));
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            append(bytes, quantise16(params.at(kLogScales, i)[a], r.logScaleMin[a], r.logScaleMax[a]));
        }
    }
    for (std::size_t i = 0; i < n; ++i) append(bytes, quantiseOpacity(*params.at(kOpacityLogits, i)));
    for (std::size_t i = 0; i < n; ++i) {
        // Keep opacity * colour exact to the colour's precision despite the 8-bit opacity.
        const float fold = sigmoid(*params.at(kOpacityLogits, i)) /
                           opacityOf(quantiseOpacity(*params.at(kOpacityLogits, i)));
        for (int c = 0; c < params.channels; ++c) {
            append(bytes, quantise16(params.at(kColours, i)[c] * fold, r.colourMin[c], r.colourMax[c]));
        }
    }
    return bytes;
}

GaussianParameters decodeBody(const unsigned char* cursor, std::size_t n, int channels,
                              const QuantisationRanges& r) {
    GaussianParameters params(n, channels);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) params.at(kMeans, i)[a] = dequantise16(take<std::uint16_t>(cursor), r.meanMin[a], r.meanMax[a]);
    }
    for (std::size_t i = 0; i < n; ++i) unpackQuaternion(take<std::uint32_t>(cursor), params.at(kRotations, i));
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            params.at(kLogScales, i)[a] = dequantise16(take<std::uint16_t>(cursor), r.logScaleMin[a], r.logScaleMax[a]);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const float opacity = opacityOf(take<std::uint8_t>(cursor));
        *params.at(kOpacityLogits, i) = std::log(opacity / (1.0f - opacity));
    }
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < channels; ++c) {
            params.at(kColours, i)[c] = dequantise16(take<std::uint16_t>(cursor), r.colourMin[c], r.colourMax[c]);
        }
    }
    return params;
}

nlohmann::json sourceJson(const VolumeMetadata& m) {
    nlohmann::json j = {{"file", m.sourceFile},         {"modality", m.modality},
                        {"type", m.sourceType},         {"channels", m.channels},
                        {"dims", {m.dims.x(), m.dims.y(), m.dims.z()}},
                        {"spacing_mm", {m.spacingMm.x(), m.spacingMm.y(), m.spacingMm.z()}},
                        {"value_min", m.valueMin},      {"value_max", m.valueMax},
                        {"background", m.background},   {"raw_bytes", m.rawSourceBytes()}};
    if (m.threshold) j["threshold"] = *m.threshold;
    return j;
}

VolumeMetadata sourceFromJson(const nlohmann::json& j) {
    VolumeMetadata m;
    m.sourceFile = j.at("file").get<std::string>();
    m.modality = j.at("modality").get<std::string>();
    m.sourceType = j.at("type").get<std::string>();
    m.channels = j.at("channels").get<int>();
    const auto dims = j.at("dims").get<std::array<int, 3>>();
    m.dims = openvdb::Vec3i(dims[0], dims[1], dims[2]);
    const auto spacing = j.at("spacing_mm").get<std::array<double, 3>>();
    m.spacingMm = openvdb::Vec3d(spacing[0], spacing[1], spacing[2]);
    m.valueMin = j.at("value_min").get<double>();
    m.valueMax = j.at("value_max").get<double>();
    m.background = j.at("background").get<double>();
    if (j.contains("threshold")) m.threshold = j.at("threshold").get<double>();
    return m;
}

/// The runs of equal labels, in order. @throw std::logic_error when a label comes
/// back after another: the format stores groups, so they must be contiguous.
nlohmann::json labelGroupsJson(const GaussianAsset& asset) {
    if (asset.labels.size() != asset.params.count()) throw std::logic_error("one label per Gaussian is needed");
    nlohmann::json groups = nlohmann::json::array();
    std::set<int> seen;
    for (std::size_t i = 0; i < asset.labels.size();) {
        const int id = asset.labels[i];
        if (!seen.insert(id).second) throw std::logic_error("the asset's labels are not grouped");
        std::size_t end = i;
        while (end < asset.labels.size() && asset.labels[end] == id) ++end;
        groups.push_back({{"id", id}, {"name", asset.labelTable.nameOf(id)}, {"count", end - i}});
        i = end;
    }
    for (const auto& [id, name] : asset.labelTable.names) {  // structures left with no Gaussian
        if (!seen.count(id)) groups.push_back({{"id", id}, {"name", name}, {"count", 0}});
    }
    return groups;
}

/// Per-Gaussian labels and their names from the header's groups.
void readLabelGroups(const nlohmann::json& groups, std::size_t count, GaussianAsset& asset) {
    for (const nlohmann::json& group : groups) {
        const int id = group.at("id").get<int>();
        const std::size_t n = group.at("count").get<std::size_t>();
        if (n > count - asset.labels.size()) throw std::runtime_error("label groups hold more Gaussians than the asset");
        asset.labelTable.names[id] = group.at("name").get<std::string>();
        asset.labels.insert(asset.labels.end(), n, id);
    }
    if (asset.labels.size() != count) throw std::runtime_error("label groups do not cover every Gaussian");
}

std::string headerJson(const GaussianAsset& asset, const QuantisationRanges& r) {
    const int channels = asset.params.channels;
    std::vector<double> matrix(16);
    for (int k = 0; k < 16; ++k) matrix[k] = asset.worldFromIndex.asPointer()[k];
    nlohmann::json header = {
        {"format", "gvr-gaussians"},
        {"count", asset.params.count()},
        {"channels", channels},
        {"cutoff_sigmas", asset.cutoffSigmas},
        {"world_from_index", matrix},
        {"value_offset", asset.mapping.offset},
        {"value_scale", asset.mapping.scale},
        {"quantisation",
         {{"mean_min", r.meanMin}, {"mean_max", r.meanMax},
          {"log_scale_min", r.logScaleMin}, {"log_scale_max", r.logScaleMax},
          {"colour_min", std::vector<float>(r.colourMin.begin(), r.colourMin.begin() + channels)},
          {"colour_max", std::vector<float>(r.colourMax.begin(), r.colourMax.begin() + channels)}}},
        {"source", sourceJson(asset.source)},
        {"fit", asset.fitSettings}};
    if (!asset.labels.empty()) header["labels"] = labelGroupsJson(asset);
    return header.dump();
}

QuantisationRanges rangesFromJson(const nlohmann::json& q, int channels) {
    QuantisationRanges r;
    r.meanMin = q.at("mean_min").get<std::array<float, 3>>();
    r.meanMax = q.at("mean_max").get<std::array<float, 3>>();
    r.logScaleMin = q.at("log_scale_min").get<std::array<float, 3>>();
    r.logScaleMax = q.at("log_scale_max").get<std::array<float, 3>>();
    const auto colourMin = q.at("colour_min").get<std::vector<float>>();
    const auto colourMax = q.at("colour_max").get<std::vector<float>>();
    if (int(colourMin.size()) != channels || int(colourMax.size()) != channels) {
        throw std::runtime_error("colour ranges do not match the channel count");
    }
    std::copy(colourMin.begin(), colourMin.end(), r.colourMin.begin());
    std::copy(colourMax.begin(), colourMax.end(), r.colourMax.begin());
    return r;
}

/// Keeps the Gaussians (and their labels) whose flag is set, in order.
void keepOnly(GaussianAsset& asset, const std::vector<bool>& keep) {
    asset.params.keepOnly(keep);
    if (asset.labels.empty()) return;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < keep.size(); ++i) {
        if (keep[i]) asset.labels[kept++] = asset.labels[i];
    }
    asset.labels.resize(kept);
}

/// Drops the Gaussians with the smallest peak amplitude, keeping @a keepCount.
void keepStrongest(GaussianAsset& asset, std::size_t keepCount) {
    const GaussianParameters& params = asset.params;
    std::vector<float> peak(params.count());
    for (std::size_t i = 0; i < params.count(); ++i) {
        const float opacity = sigmoid(*params.at(kOpacityLogits, i));
        for (int c = 0; c < params.channels; ++c) {
            peak[i] = std::max(peak[i], std::abs(opacity * params.at(kColours, i)[c]));
        }
    }
    std::vector<std::size_t> order(params.count());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return peak[a] > peak[b]; });
    std::vector<bool> keep(params.count(), false);
    for (std::size_t k = 0; k < keepCount; ++k) keep[order[k]] = true;
    keepOnly(asset, keep);
}

}  // namespace

std::size_t assetBytesPerGaussian(int channels) { return 17 + 2 * std::size_t(channels); }

std::uint64_t assetFileBytes(const GaussianAsset& asset) {
    return kPreambleBytes + headerJson(asset, rangesOf(asset.params)).size() +
           asset.params.count() * assetBytesPerGaussian(asset.params.channels) + kChecksumBytes;
}

std::size_t assetCapacity(const GaussianAsset& asset, std::uint64_t maxBytes) {
    // The header grows with the count's digits and the ranges; keep 256 bytes of slack.
    const std::uint64_t fixed = kPreambleBytes + headerJson(asset, rangesOf(asset.params)).size() + 256 +
                                kChecksumBytes;
    if (maxBytes <= fixed) return 0;
    return std::size_t((maxBytes - fixed) / assetBytesPerGaussian(asset.params.channels));
}

GaussianAsset withLabels(const GaussianAsset& asset, const std::vector<int>& shown) {
    if (asset.labels.empty()) return asset;
    GaussianAsset subset = asset;
    std::vector<bool> keep(asset.labels.size());
    for (std::size_t i = 0; i < keep.size(); ++i) {
        keep[i] = std::binary_search(shown.begin(), shown.end(), asset.labels[i]);
    }
    keepOnly(subset, keep);
    subset.labelTable.names.clear();
    for (int id : shown) subset.labelTable.names[id] = asset.labelTable.nameOf(id);
    return subset;
}

GaussianAsset selectStructures(const GaussianAsset& asset, const std::string& show, const std::string& hide,
                               const std::string& path) {
    if (show.empty() && hide.empty()) return asset;
    if (asset.labelTable.names.empty()) {
        throw InputError(path, "has no structures to show or hide; fit it with gvr fit --labels");
    }
    return withLabels(asset, shownLabels(asset.labelTable, show, hide));
}

GaussianParameters quantisedCopy(const GaussianParameters& params) {
    const QuantisationRanges ranges = rangesOf(params);
    const std::string body = encodeBody(params, ranges);
    return decodeBody(reinterpret_cast<const unsigned char*>(body.data()), params.count(), params.channels, ranges);
}

std::size_t writeAsset(const std::string& path, GaussianAsset& asset, std::uint64_t maxBytes) {
    const std::size_t before = asset.params.count();
    while (maxBytes > 0 && asset.params.count() > 0 && assetFileBytes(asset) > maxBytes) {
        const std::uint64_t excess = assetFileBytes(asset) - maxBytes;
        const std::size_t drop = std::size_t(excess / assetBytesPerGaussian(asset.params.channels)) + 1;
        keepStrongest(asset, asset.params.count() - std::min(drop, asset.params.count()));
    }
    const QuantisationRanges ranges = rangesOf(asset.params);
    const std::string header = headerJson(asset, ranges);
    std::string bytes(kMagic, sizeof kMagic);
    append(bytes, kAssetVersion);
    append(bytes, std::uint32_t(header.size()));
    bytes += header;
    bytes += encodeBody(asset.params, ranges);
    append(bytes, std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size()))));
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw InputError(path, "cannot write the asset");
    });
    return before - asset.params.count();
}

bool isAssetFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[sizeof kMagic] = {};
    in.read(magic, sizeof magic);
    return in && std::equal(magic, magic + sizeof magic, kMagic);
}

GaussianAsset readAsset(const std::string& path) {
    if (!isAssetFile(path)) throw InputError(path, "not a gvr asset (no GVRASSET magic)");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::uint64_t size = std::uint64_t(in.tellg());
    if (size < kPreambleBytes + kChecksumBytes) throw InputError(path, "truncated asset");
    std::string bytes(size, '\0');
    in.seekg(0);
    in.read(bytes.data(), std::streamsize(size));
    const auto* cursor = reinterpret_cast<const unsigned char*>(bytes.data()) + sizeof kMagic;
    const std::uint32_t version = take<std::uint32_t>(cursor);
    if (version != kAssetVersion) {
        throw InputError(path, "unsupported asset version " + std::to_string(version) +
                                   " (this gvr reads version " + std::to_string(kAssetVersion) + ")");
    }
    const std::uint32_t headerBytes = take<std::uint32_t>(cursor);
    if (headerBytes > size - kPreambleBytes - kChecksumBytes) throw InputError(path, "truncated asset header");

    GaussianAsset asset;
    QuantisationRanges ranges;
    std::size_t count = 0;
    int channels = 1;
    try {
        const nlohmann::json header = nlohmann::json::parse(bytes.begin() + kPreambleBytes,
                                                            bytes.begin() + kPreambleBytes + headerBytes);
        count = header.at("count").get<std::size_t>();
        channels = header.at("channels").get<int>();
        if ((channels != 1 && channels != 3) || count > kMaxGaussians) {
            throw std::runtime_error("impossible count or channels");
        }
        asset.cutoffSigmas = header.at("cutoff_sigmas").get<float>();
        const auto matrix = header.at("world_from_index").get<std::array<double, 16>>();
        asset.worldFromIndex = openvdb::math::Mat4d(matrix.data());
        asset.mapping.offset = header.at("value_offset").get<std::array<double, 3>>();
        asset.mapping.scale = header.at("value_scale").get<double>();
        ranges = rangesFromJson(header.at("quantisation"), channels);
        asset.source = sourceFromJson(header.at("source"));
        asset.fitSettings = header.at("fit");
        if (header.contains("labels")) readLabelGroups(header.at("labels"), count, asset);
    } catch (const std::exception& error) {
        throw InputError(path, std::string("corrupt asset header: ") + error.what());
    }
    const std::uint64_t expected =
        kPreambleBytes + headerBytes + count * assetBytesPerGaussian(channels) + kChecksumBytes;
    if (size != expected) {
        throw InputError(path, (size < expected ? "truncated asset: " : "asset has trailing bytes: ") +
                                   std::to_string(size) + " bytes, the header implies " +
                                   std::to_string(expected));
    }
    std::uint32_t stored;
    std::memcpy(&stored, bytes.data() + size - kChecksumBytes, sizeof stored);
    const auto computed = std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), uInt(size - kChecksumBytes)));
    if (stored != computed) throw InputError(path, "corrupt asset: checksum mismatch");

    asset.params = decodeBody(reinterpret_cast<const unsigned char*>(bytes.data()) + kPreambleBytes + headerBytes,
                              count, channels, ranges);
    if (!asset.params.allFinite() || !std::isfinite(asset.cutoffSigmas) || !(asset.mapping.scale != 0.0)) {
        throw InputError(path, "corrupt asset: non-finite values");
    }
    return asset;
}

}  // namespace gvr
