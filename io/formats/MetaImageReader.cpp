// ITK MetaImage: a text header of "Key = Value" lines (.mhd, with the samples in a
// separate file) or the same header followed by the samples (.mha, ElementDataFile = LOCAL).

#include "io/formats/Readers.h"
#include "io/formats/SampleFile.h"
#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace gvr {

namespace {

struct MetaHeader {
    std::map<std::string, std::string> fields;
    std::uint64_t endOffset = 0;  // where LOCAL data begins
};

std::string trim(const std::string& text) {
    const auto begin = text.find_first_not_of(" \t\r");
    if (begin == std::string::npos) return "";
    return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

/// True when @a file, links resolved, lies in @a folder or below it.
bool liesBelow(const std::filesystem::path& file, const std::filesystem::path& folder) {
    namespace fs = std::filesystem;
    const fs::path base = fs::weakly_canonical(folder.empty() ? fs::path(".") : folder);
    const fs::path resolved = fs::weakly_canonical(file);
    return std::mismatch(base.begin(), base.end(), resolved.begin(), resolved.end()).first == base.end();
}

/// The header names the data file, so its name may be anything: too long, a
/// folder, nothing at all.
void checkDataFile(const std::string& header, const std::string& samplesPath) {
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(samplesPath, error);
    if (!std::filesystem::exists(status)) {
        const std::string why = error && error != std::errc::no_such_file_or_directory ? ": " + error.message() : "";
        throw InputError(header, "ElementDataFile " + samplesPath + " does not exist" + why);
    }
    if (!std::filesystem::is_regular_file(status)) {
        throw InputError(header, "ElementDataFile " + samplesPath + " is not a regular file");
    }
}

/// Reads "Key = Value" lines up to ElementDataFile, which MetaImage requires last.
MetaHeader readHeader(const std::string& path);

/// Where @a header's samples are: @a path itself for LOCAL, else the named file
/// beside it, which may not be the header itself.
std::string dataFileOf(const MetaHeader& header, const std::string& path);

/// Reads "Key = Value" lines up to ElementDataFile, which MetaImage requires last.
MetaHeader readHeader(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot open file");
    MetaHeader header;
    std::string line;
    constexpr std::size_t kMaxHeaderLines = 200;
    for (std::size_t lineCount = 0; lineCount < kMaxHeaderLines && std::getline(in, line); ++lineCount) {
        const auto equals = line.find('=');
        if (equals == std::string::npos) {
            throw InputError(path, "corrupt MetaImage header: line '" + line.substr(0, 40) + "' is not 'Key = Value'");
        }
        const std::string key = trim(line.substr(0, equals));
        header.fields[key] = trim(line.substr(equals + 1));
        if (key == "ElementDataFile") {
            header.endOffset = std::uint64_t(in.tellg());
            return header;
        }
    }
    throw InputError(path, "corrupt MetaImage header: no ElementDataFile line");
}

const std::string& field(const MetaHeader& header, const std::string& key, const std::string& path) {
    const auto found = header.fields.find(key);
    if (found == header.fields.end()) throw InputError(path, "MetaImage header lacks " + key);
    return found->second;
}

std::string dataFileOf(const MetaHeader& header, const std::string& path) {
    const std::string dataFile = field(header, "ElementDataFile", path);
    if (dataFile == "LIST" || dataFile.find('%') != std::string::npos) {
        throw InputError(path, "MetaImage ElementDataFile '" + dataFile + "' (slice lists) is not supported");
    }
    if (dataFile == "LOCAL") return path;
    const std::filesystem::path samples = std::filesystem::path(path).parent_path() / dataFile;
    std::error_code error;
    if (std::filesystem::equivalent(samples, path, error)) {
        throw InputError(path, "ElementDataFile names the header itself (write LOCAL for samples after the header)");
    }
    return samples.string();
}

std::vector<double> numbers(const MetaHeader& header, const std::string& key, std::size_t count,
                            const std::string& path) {
    std::istringstream in(field(header, key, path));
    std::vector<double> values(count);
    for (double& value : values) {
        if (!(in >> value)) {
            throw InputError(path, "MetaImage " + key + " needs " + std::to_string(count) + " numbers");
        }
    }
    return values;
}

std::vector<double> numbersOr(const MetaHeader& header, const std::string& key, std::vector<double> fallback,
                              const std::string& path) {
    if (!header.fields.count(key)) return fallback;
    return numbers(header, key, fallback.size(), path);
}

/// A small count (NDims, channels), which a header may give as any number at all.
int countOr(const MetaHeader& header, const std::string& key, double fallback, const std::string& path) {
    const double value = numbersOr(header, key, {fallback}, path)[0];
    if (!(value >= 1 && value <= 64) || value != std::floor(value)) {
        throw InputError(path, "MetaImage " + key + " is " + field(header, key, path) + ", not a count");
    }
    return int(value);
}

SampleType sampleTypeOf(const std::string& elementType, const std::string& path) {
    static const std::map<std::string, SampleType> types = {
        {"MET_UCHAR", SampleType::UInt8},   {"MET_CHAR", SampleType::Int8},     {"MET_USHORT", SampleType::UInt16},
        {"MET_SHORT", SampleType::Int16},   {"MET_UINT", SampleType::UInt32},   {"MET_INT", SampleType::Int32},
        {"MET_FLOAT", SampleType::Float32}, {"MET_DOUBLE", SampleType::Float64}};
    const auto found = types.find(elementType);
    if (found == types.end()) {
        throw InputError(path, "unsupported MetaImage ElementType " + elementType);
    }
    return found->second;
}

bool isTrue(const MetaHeader& header, const std::string& key) {
    const auto found = header.fields.find(key);
    return found != header.fields.end() && (found->second == "True" || found->second == "true");
}

/// MetaImage geometry is LPS like ITK; gvr's world is RAS, so x and y change sign.
/// TransformMatrix lists the direction of each index axis in turn.
openvdb::math::Mat4d worldFromIndexOf(const MetaHeader& header, int ndims, const std::string& path) {
    const std::size_t n = std::size_t(ndims);
    std::vector<double> identity(n * n, 0.0);
    for (std::size_t a = 0; a < n; ++a) identity[a * n + a] = 1.0;
    const std::vector<double> spacing = numbersOr(header, "ElementSpacing", std::vector<double>(n, 1.0), path);
    std::vector<double> origin = numbersOr(header, "Offset", std::vector<double>(n, 0.0), path);
    origin = numbersOr(header, "Position", origin, path);
    origin = numbersOr(header, "Origin", origin, path);
    std::vector<double> directions = numbersOr(header, "TransformMatrix", identity, path);
    directions = numbersOr(header, "Rotation", directions, path);
    directions = numbersOr(header, "Orientation", directions, path);

    const double sign[3] = {-1, -1, 1};
    double rows[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    for (std::size_t r = 0; r < n; ++r) {
        for (std::size_t axis = 0; axis < n; ++axis) {
            rows[r][axis] = sign[r] * directions[axis * n + r] * spacing[axis];
        }
        rows[r][3] = sign[r] * origin[r];
    }
    return worldFromIndexRows(rows);
}

}  // namespace

std::string metaImageDataFile(const std::string& path) { return dataFileOf(readHeader(path), path); }

DenseVolume readMetaImage(const std::string& path, const ReadOptions& options) {
    const MetaHeader header = readHeader(path);
    const int ndims = countOr(header, "NDims", 0.0, path);
    if (ndims != 2 && ndims != 3) {
        throw InputError(path, "MetaImage NDims is " + std::to_string(ndims) + "; gvr reads 2 or 3");
    }
    const std::vector<double> size = numbers(header, "DimSize", std::size_t(ndims), path);
    DenseVolume volume;
    // Out-of-range sizes become 0 so that reserveSamples() rejects them by name.
    const auto dimension = [&](std::size_t axis) -> std::int64_t {
        if (axis >= size.size()) return 1;
        return size[axis] >= 1 && size[axis] < 9e18 ? std::int64_t(size[axis]) : 0;
    };
    volume.dims = {dimension(0), dimension(1), dimension(2)};
    volume.type = sampleTypeOf(field(header, "ElementType", path), path);
    volume.channels = countOr(header, "ElementNumberOfChannels", 1.0, path);
    if (volume.channels != 1 && volume.channels != 3) {
        throw InputError(
            path, "MetaImage has " + std::to_string(volume.channels) + " channels; gvr reads 1 (grey) or 3 (RGB)");
    }
    volume.worldFromIndex = worldFromIndexOf(header, ndims, path);
    const bool bigEndian = isTrue(header, "BinaryDataByteOrderMSB") || isTrue(header, "ElementByteOrderMSB");
    const std::string dataFile = field(header, "ElementDataFile", path);
    reserveSamples(volume, path);  // the sample reader allocates as data arrives

    const bool local = dataFile == "LOCAL";
    const std::string samplesPath = dataFileOf(header, path);
    if (!local) checkDataFile(path, samplesPath);
    if (!local && !options.dataFilesAnywhere && !liesBelow(samplesPath, std::filesystem::path(path).parent_path())) {
        throw InputError(path, "ElementDataFile " + dataFile +
                                   " lies outside the header's folder (allow it with `data_files_anywhere`)");
    }
    const std::uint64_t offset = local ? header.endOffset : 0;
    if (isTrue(header, "CompressedData")) {
        readDeflatedSamples(samplesPath, offset, bigEndian, volume);
    } else {
        readPlainSamples(samplesPath, offset, bigEndian, volume);
    }
    if (options.progress) options.progress(1.0);
    return volume;
}

}  // namespace gvr
