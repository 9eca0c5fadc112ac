#include "io/asset/AssetFile.h"

#include "io/asset/AssetBodyV1.h"
#include "io/asset/AssetResidual.h"
#include "io/formats/FileKind.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "io/guard/ByteOrder.h"
#include "io/guard/InputFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/GaussianKernel.h"

#include <zlib.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>
#include <set>

namespace gvr {

namespace {

constexpr std::size_t kPreambleBytes = 16;
constexpr std::size_t kChecksumBytes = 4;
constexpr std::size_t kMaxGaussians = std::size_t(1) << 31;
constexpr std::size_t kMaxGaussiansPerBodyByte = 8;
constexpr std::size_t kMaxHeaderDepth = 64;
constexpr double kMaxWorldMm = 1e9;        // a thousand kilometres
constexpr float kMaxMeanVoxels = 1 << 24;  // where float positions still step by a voxel
constexpr float kLogScaleSlack = 0.5f;     // quantisation may step a little past the kernel's range

nlohmann::json sourceJson(const VolumeMetadata& m) {
    nlohmann::json j = {{"file", m.sourceFile},
                        {"modality", m.modality},
                        {"type", m.sourceType},
                        {"channels", m.channels},
                        {"dims", {m.dims.x(), m.dims.y(), m.dims.z()}},
                        {"spacing_mm", {m.spacingMm.x(), m.spacingMm.y(), m.spacingMm.z()}},
                        {"value_min", m.valueMin},
                        {"value_max", m.valueMax},
                        {"background", m.background},
                        {"raw_bytes", m.rawSourceBytes()}};
    if (m.threshold) j["threshold"] = *m.threshold;
    if (m.thresholdAbove) j["threshold_above"] = *m.thresholdAbove;
    if (m.padding) j["padding"] = {{"value", *m.padding}, {"voxels", m.paddingVoxels}};
    j["stored_slope"] = m.storedSlope;
    j["stored_intercept"] = m.storedIntercept;
    if (m.niftiCodes) j["nifti_codes"] = {m.niftiCodes->sform, m.niftiCodes->qform, m.niftiCodes->xyztUnits};
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
    if (j.contains("threshold_above")) m.thresholdAbove = j.at("threshold_above").get<double>();
    if (j.contains("padding")) {
        m.padding = j.at("padding").at("value").get<double>();
        m.paddingVoxels = j.at("padding").at("voxels").get<std::uint64_t>();
    }
    m.storedSlope = j.value("stored_slope", 1.0);
    m.storedIntercept = j.value("stored_intercept", 0.0);
    if (j.contains("nifti_codes")) {
        const auto codes = j.at("nifti_codes").get<std::array<int, 3>>();
        m.niftiCodes = NiftiCodes{codes[0], codes[1], codes[2]};
    }
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
        if (n > count - asset.labels.size())
            throw std::runtime_error("label groups hold more Gaussians than the asset");
        asset.labelTable.names[id] = group.at("name").get<std::string>();
        asset.labels.insert(asset.labels.end(), n, id);
    }
    if (asset.labels.size() != count) throw std::runtime_error("label groups do not cover every Gaussian");
}

std::string headerJson(const GaussianAsset& asset, const nlohmann::json& quantisation) {
    std::vector<double> matrix(16);
    for (int k = 0; k < 16; ++k) matrix[k] = asset.worldFromIndex.asPointer()[k];
    nlohmann::json header = {{"format", "gvr-gaussians"},          {"count", asset.params.count()},
                             {"channels", asset.params.channels},  {"cutoff_sigmas", asset.cutoffSigmas},
                             {"world_from_index", matrix},         {"value_offset", asset.mapping.offset},
                             {"value_scale", asset.mapping.scale}, {"quantisation", quantisation},
                             {"source", sourceJson(asset.source)}, {"fit", asset.fitSettings}};
    if (!asset.labels.empty()) header["labels"] = labelGroupsJson(asset);
    return jsonText(header);
}

GaussianParameters permuted(const GaussianParameters& params, const std::vector<std::size_t>& order) {
    GaussianParameters out(order.size(), params.channels);
    for (int g = 0; g < kGroupCount; ++g) {
        const auto group = ParameterGroup(g);
        const int width = params.width(group);
        for (std::size_t k = 0; k < order.size(); ++k) {
            std::copy_n(params.at(group, order[k]), width, out.at(group, k));
        }
    }
    return out;
}

/// Label groups stay as they are; inside each, Morton order makes the position
/// deltas small, which is what the entropy coder lives on.
void sortForStorage(GaussianAsset& asset, const QuantisationV2& quantisation) {
    const std::size_t n = asset.params.count();
    std::vector<std::uint64_t> group(n, 0), code(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (i > 0 && !asset.labels.empty()) group[i] = group[i - 1] + (asset.labels[i] != asset.labels[i - 1]);
        code[i] = quantisation.mortonCode(asset.params.at(kMeans, i));
    }
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return group[a] != group[b] ? group[a] < group[b] : code[a] < code[b];
    });
    asset.params = permuted(asset.params, order);
}

}  // namespace

std::string encodeAsset(GaussianAsset& asset) {
    const QuantisationV2 quantisation(asset.params, asset.encoding);
    sortForStorage(asset, quantisation);
    const std::string header = headerJson(asset, quantisation.json());
    std::string bytes(kAssetMagic, sizeof kAssetMagic);
    appendLittleEndian(bytes, kAssetVersion);
    appendLittleEndian(bytes, std::uint32_t(header.size()));
    bytes += header;
    bytes += encodeAssetBodyV2(asset.params, quantisation);
    appendLittleEndian(bytes,
                       std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size()))));
    // A layer read from a file goes back over the same Gaussians' bytes: a decoded
    // asset's parameters quantise to what they were (a test holds save to the byte).
    return asset.residual ? withResidualLayer(bytes, *asset.residual) : bytes;
}

namespace {

/// Refuses a count that the file cannot hold, before anything is allocated for it.
void checkCountAgainstSize(std::uint32_t version, std::size_t count, int channels, std::uint64_t bodyBytes) {
    if (version == 1 && count * assetV1BytesPerGaussian(channels) != bodyBytes) {
        throw std::runtime_error("the count implies " + std::to_string(count * assetV1BytesPerGaussian(channels)) +
                                 " bytes of Gaussians, the file holds " + std::to_string(bodyBytes) +
                                 " (truncated, or trailing bytes)");
    }
    // zstd packs a plane of equal bytes into very little, but a fit's Gaussians
    // differ: gvr's own files hold 2 bytes a Gaussian or more.
    if (version >= 2 && count > kMaxGaussiansPerBodyByte * bodyBytes) {
        throw std::runtime_error("the count is impossible for a body of " + std::to_string(bodyBytes) +
                                 " bytes (at most " + std::to_string(kMaxGaussiansPerBodyByte) + " Gaussians a byte)");
    }
    int floats = 0;
    for (int g = 0; g < kGroupCount; ++g) floats += groupWidth(ParameterGroup(g), channels);
    // The parameters and about as much again while the streams decode.
    const std::uint64_t decodedBytes = std::uint64_t(count) * floats * sizeof(float) * 2;
    if (decodedBytes > availableMemoryBytes()) {
        throw std::runtime_error(std::to_string(count) + " Gaussians would need " + std::to_string(decodedBytes >> 20) +
                                 " MiB to decode; " + std::to_string(availableMemoryBytes() >> 20) +
                                 " MiB are available");
    }
}

/// The deepest nesting of arrays and objects in JSON text, strings skipped: the
/// parser recurses once a level, so a header nested 100,000 deep would overflow
/// the stack before any other check.
std::size_t jsonDepth(std::string_view text) {
    std::size_t depth = 0, deepest = 0;
    bool inString = false;
    for (std::size_t n = 0; n < text.size(); ++n) {
        const char c = text[n];
        if (inString) {
            if (c == '\\')
                ++n;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

/// Refuses decoded fields that gvr never writes and that would overflow later:
/// the value mapping beyond float, a transform that is not affine or reaches
/// beyond kMaxWorldMm, shapes outside the kernel's log-scale range, means far
/// outside any volume.
void checkAssetFields(const GaussianAsset& asset, const std::string& path) {
    const ValueMapping& m = asset.mapping;
    const auto withinFloat = [](double v) { return std::isfinite(v) && std::abs(v) <= double(FLT_MAX); };
    if (!(m.scale > 0.0) || !withinFloat(m.scale) || !withinFloat(m.offset[0]) || !withinFloat(m.offset[1]) ||
        !withinFloat(m.offset[2])) {
        throw InputError(path,
                         "corrupt asset: value_scale and value_offset must be finite, within the float "
                         "range, and the scale positive");
    }
    const openvdb::math::Mat4d& t = asset.worldFromIndex;
    bool affine = t(0, 3) == 0.0 && t(1, 3) == 0.0 && t(2, 3) == 0.0 && t(3, 3) == 1.0;
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) affine = affine && std::isfinite(t(i, j)) && std::abs(t(i, j)) <= kMaxWorldMm;
    }
    if (!affine) {
        throw InputError(path, "corrupt asset: world_from_index must be affine with entries within +-" +
                                   std::to_string(int(kMaxWorldMm)) + " mm");
    }
    for (std::size_t g = 0; g < asset.params.count(); ++g) {
        const float* logScale = asset.params.at(kLogScales, g);
        const float* mean = asset.params.at(kMeans, g);
        for (int a = 0; a < 3; ++a) {
            if (!(logScale[a] >= kMinLogScale - kLogScaleSlack && logScale[a] <= kMaxLogScale + kLogScaleSlack)) {
                throw InputError(path, "corrupt asset: Gaussian " + std::to_string(g) + " has log-scale " +
                                           std::to_string(logScale[a]) + " (gvr writes " +
                                           std::to_string(kMinLogScale) + " to " + std::to_string(kMaxLogScale) + ")");
            }
            if (!(std::abs(mean[a]) <= kMaxMeanVoxels)) {
                throw InputError(path, "corrupt asset: Gaussian " + std::to_string(g) + " lies at " +
                                           std::to_string(mean[a]) + " voxels, beyond any volume");
            }
        }
    }
}

/// The Gaussians' part of a format-3 body; the residual layer after it goes to @a asset.
std::string_view splitOffResidual(std::string_view body, const nlohmann::json& description, GaussianAsset& asset,
                                  int channels, const std::string& path) {
    const auto sectionBytes = description.at("section_bytes").get<std::uint64_t>();
    if (sectionBytes > body.size()) throw std::runtime_error("the residual section runs past the body");
    const openvdb::Vec3i dims = asset.source.dims;
    if (dims.x() < 1 || dims.y() < 1 || dims.z() < 1) throw std::runtime_error("a residual layer over no voxels");
    checkVolumeFitsInMemory(path, {dims.x(), dims.y(), dims.z()}, channels, 3 * sizeof(float),
                            "decode its residual layer");
    asset.residual = std::make_shared<const ResidualLayer>(decodeResidualSection(
        body.substr(body.size() - sectionBytes), description, openvdb::Coord(dims.x(), dims.y(), dims.z()), channels));
    return body.substr(0, body.size() - sectionBytes);
}

}  // namespace

std::string withResidualLayer(std::string_view assetBytes, const ResidualLayer& layer) {
    const auto* cursor = reinterpret_cast<const unsigned char*>(assetBytes.data()) + sizeof kAssetMagic;
    const std::uint32_t version = takeLittleEndian<std::uint32_t>(cursor);
    const std::uint32_t headerBytes = takeLittleEndian<std::uint32_t>(cursor);
    if (version != kAssetVersion) throw std::logic_error("a residual layer goes onto a format-2 asset's bytes");
    nlohmann::json header = nlohmann::json::parse(assetBytes.substr(kPreambleBytes, headerBytes));
    nlohmann::json description;
    const std::string section = encodeResidualSection(layer, description);
    header["residual"] = description;
    const std::string text = jsonText(header);
    std::string bytes(kAssetMagic, sizeof kAssetMagic);
    appendLittleEndian(bytes, kBoundedAssetVersion);
    appendLittleEndian(bytes, std::uint32_t(text.size()));
    bytes += text;
    bytes += assetBytes.substr(kPreambleBytes + headerBytes,
                               assetBytes.size() - kPreambleBytes - headerBytes - kChecksumBytes);
    bytes += section;
    appendLittleEndian(bytes,
                       std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size()))));
    return bytes;
}

double assetEstimatedBytesPerGaussian(const GaussianAsset& asset, double count) {
    const openvdb::Vec3i& dims = asset.source.dims;
    const double voxels = double(dims.x()) * double(dims.y()) * double(dims.z());
    return estimatedBytesPerGaussian(asset.encoding, asset.params.channels, voxels, count);
}

std::uint64_t assetFileBytes(const GaussianAsset& asset) {
    GaussianAsset copy = asset;
    return encodeAsset(copy).size();
}

std::size_t assetRoom(GaussianAsset& asset, std::uint64_t maxBytes) {
    const std::uint64_t bytes = encodeAsset(asset).size();
    if (bytes >= maxBytes || asset.params.count() == 0) return 0;
    const double perGaussian = double(bytes) / double(asset.params.count());
    return std::size_t(double(maxBytes - bytes) / perGaussian);
}

std::size_t assetCapacity(const GaussianAsset& asset, std::uint64_t maxBytes) {
    // The header grows with the count's digits and the ranges, and every zstd frame
    // has its own header: keep 512 bytes of slack.
    const QuantisationV2 quantisation(asset.params, asset.encoding);
    const std::uint64_t fixed = kPreambleBytes + headerJson(asset, quantisation.json()).size() + 512 + kChecksumBytes;
    if (maxBytes <= fixed) return 0;
    // Positions cost more per Gaussian when there are fewer: settle the count by iterating.
    const double room = double(maxBytes - fixed);
    double count = room / 8.0;
    for (int k = 0; k < 8; ++k) count = room / assetEstimatedBytesPerGaussian(asset, count);
    return std::size_t(count);
}

GaussianParameters quantisedCopy(const GaussianParameters& params, const AssetEncoding& encoding) {
    const QuantisationV2 quantisation(params, encoding);
    return roundTripAssetBodyV2(params, quantisation);
}

std::string encodeAssetWithin(GaussianAsset& asset, std::uint64_t maxBytes) {
    std::string bytes = encodeAsset(asset);
    while (maxBytes > 0 && asset.params.count() > 0 && bytes.size() > maxBytes) {
        const double perGaussian = double(bytes.size()) / double(asset.params.count());
        const std::size_t drop = std::size_t(double(bytes.size() - maxBytes) / perGaussian) + 1;
        keepStrongest(asset, asset.params.count() - std::min(drop, asset.params.count()));
        bytes = encodeAsset(asset);
    }
    return bytes;
}

std::size_t fitAssetInto(GaussianAsset& asset, std::uint64_t maxBytes) {
    const std::size_t before = asset.params.count();
    encodeAssetWithin(asset, maxBytes);
    return before - asset.params.count();
}

std::size_t writeAsset(const std::string& path, GaussianAsset& asset, std::uint64_t maxBytes) {
    const std::size_t before = asset.params.count();
    writeAssetBytes(path, encodeAssetWithin(asset, maxBytes));
    return before - asset.params.count();
}

void writeAssetBytes(const std::string& path, const std::string& bytes) {
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw InputError(path, "cannot write the asset");
    });
}

GaussianAsset readAsset(const std::string& path) {
    requireRegularFile(path);
    if (fileKind(path) != FileKind::Asset) throw InputError(path, "not a gvr asset (no GVRASSET magic)");
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::uint64_t size = std::uint64_t(in.tellg());
    if (size < kPreambleBytes + kChecksumBytes) throw InputError(path, "truncated asset");
    std::string bytes(size, '\0');
    in.seekg(0);
    in.read(bytes.data(), std::streamsize(size));
    return decodeAsset(bytes, path);
}

GaussianAsset decodeAsset(std::string_view bytes, const std::string& path) {
    const std::uint64_t size = bytes.size();
    if (size < kPreambleBytes + kChecksumBytes ||
        !std::equal(kAssetMagic, kAssetMagic + sizeof kAssetMagic, bytes.data())) {
        throw InputError(path, "not a gvr asset (no GVRASSET magic)");
    }
    const auto* cursor = reinterpret_cast<const unsigned char*>(bytes.data()) + sizeof kAssetMagic;
    const std::uint32_t version = takeLittleEndian<std::uint32_t>(cursor);
    if (version != 1 && version != kAssetVersion && version != kBoundedAssetVersion) {
        throw InputError(path, "unsupported asset version " + std::to_string(version) +
                                   " (this gvr reads versions 1 to " + std::to_string(kBoundedAssetVersion) + ")");
    }
    const std::uint32_t headerBytes = takeLittleEndian<std::uint32_t>(cursor);
    if (headerBytes > size - kPreambleBytes - kChecksumBytes) throw InputError(path, "truncated asset header");

    GaussianAsset asset;
    asset.formatVersion = version;
    nlohmann::json quantisation, residual;
    std::size_t count = 0;
    int channels = 1;
    if (jsonDepth(bytes.substr(kPreambleBytes, headerBytes)) > kMaxHeaderDepth) {
        throw InputError(path,
                         "corrupt asset header: JSON nested more than " + std::to_string(kMaxHeaderDepth) + " deep");
    }
    try {
        const nlohmann::json header =
            nlohmann::json::parse(bytes.begin() + kPreambleBytes, bytes.begin() + kPreambleBytes + headerBytes);
        count = header.at("count").get<std::size_t>();
        channels = header.at("channels").get<int>();
        if ((channels != 1 && channels != 3) || count > kMaxGaussians) {
            throw std::runtime_error("impossible count or channels");
        }
        checkCountAgainstSize(version, count, channels, size - kPreambleBytes - headerBytes - kChecksumBytes);
        asset.cutoffSigmas = header.at("cutoff_sigmas").get<float>();
        const auto matrix = header.at("world_from_index").get<std::array<double, 16>>();
        asset.worldFromIndex = openvdb::math::Mat4d(matrix.data());
        asset.mapping.offset = header.at("value_offset").get<std::array<double, 3>>();
        asset.mapping.scale = header.at("value_scale").get<double>();
        quantisation = header.at("quantisation");
        asset.source = sourceFromJson(header.at("source"));
        asset.fitSettings = header.at("fit");
        if (header.contains("labels")) readLabelGroups(header.at("labels"), count, asset);
        if (version == kBoundedAssetVersion) residual = header.at("residual");
    } catch (const std::exception& error) {
        throw InputError(path, std::string("corrupt asset header: ") + error.what());
    }
    std::uint32_t stored;
    std::memcpy(&stored, bytes.data() + size - kChecksumBytes, sizeof stored);
    const auto computed =
        std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), uInt(size - kChecksumBytes)));
    if (stored != computed) throw InputError(path, "corrupt asset: checksum mismatch (truncated or damaged)");

    std::string_view body(bytes.data() + kPreambleBytes + headerBytes,
                          size - kPreambleBytes - headerBytes - kChecksumBytes);
    try {
        if (!residual.is_null()) body = splitOffResidual(body, residual, asset, channels, path);
        if (version == 1) {
            asset.params = decodeAssetBodyV1(body, count, channels, quantisation);
        } else {
            asset.params = decodeAssetBodyV2(body, count, QuantisationV2(quantisation, channels));
        }
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& error) {
        throw InputError(path, std::string("corrupt asset body: ") + error.what());
    }
    if (!asset.params.allFinite() || !std::isfinite(asset.cutoffSigmas) || !(asset.mapping.scale != 0.0)) {
        throw InputError(path, "corrupt asset: non-finite values");
    }
    // Valid numbers can still describe nothing usable: a fit never writes these.
    if (!(asset.cutoffSigmas >= 1.0f && asset.cutoffSigmas <= 10.0f)) {
        throw InputError(
            path, "corrupt asset: cutoff of " + std::to_string(asset.cutoffSigmas) + " sigmas (gvr writes 1 to 10)");
    }
    const double determinant = asset.worldFromIndex.getMat3().det();
    if (!std::isfinite(determinant) || std::abs(determinant) < 1e-12) {
        throw InputError(path, "corrupt asset: its index-to-world transform is singular or not finite");
    }
    checkAssetFields(asset, path);
    return asset;
}

}  // namespace gvr
