#include "VdbLengths.h"

#include "Error.h"

#include <openvdb/version.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <fstream>
#include <string>

namespace gvr {

namespace {

class LengthWalker {
public:
    explicit LengthWalker(const std::string& path) : mPath(path), mIn(path, std::ios::binary | std::ios::ate) {
        if (!mIn) throw InputError(path, "cannot open file");
        mSize = std::uint64_t(mIn.tellg());
        mIn.seekg(0);
    }

    template <typename T>
    T read(const char* what) {
        T value{};
        mIn.read(reinterpret_cast<char*>(&value), sizeof value);
        if (!mIn) throw InputError(mPath, std::string("truncated VDB file: it ends inside ") + what);
        return value;
    }

    void skip(std::uint64_t bytes, const char* what) {
        requireLeft(bytes, what);
        mIn.seekg(std::streamoff(bytes), std::ios::cur);
    }

    /// A 32-bit length followed by that many bytes: strings and metadata values.
    void skipCounted(const char* what) { skip(read<std::uint32_t>(what), what); }

    std::string readCounted(const char* what) {
        const std::uint32_t length = read<std::uint32_t>(what);
        requireLeft(length, what);
        std::string text(length, '\0');
        mIn.read(text.data(), length);
        return text;
    }

    /// MetaMap: a count, then per entry a name, a type name and a sized value.
    void skipMetadata(const char* what) {
        const std::uint32_t count = read<std::uint32_t>(what);
        if (count > left() / 12) {  // each entry holds at least three 4-byte lengths
            throw InputError(mPath, "corrupt VDB file: " + std::string(what) + " claims " + std::to_string(count) +
                                        " entries, more than the file can hold");
        }
        for (std::uint32_t k = 0; k < count; ++k) {
            skipCounted("a metadata name");
            const std::string type = readCounted("a metadata type name");
            const std::uint32_t size = read<std::uint32_t>("a metadata value");
            skip(size, "a metadata value");
            checkValueSize(type, size);
            if (type == "__delayedload") checkDelayedLoad(size);
        }
    }

    void seek(std::int64_t position, const char* what) {
        if (position < std::int64_t(mIn.tellg()) || std::uint64_t(position) > mSize) {
            throw InputError(mPath, std::string("corrupt VDB file: ") + what + " points outside the file");
        }
        mIn.seekg(position);
    }

private:
    std::uint64_t left() { return mSize - std::uint64_t(mIn.tellg()); }

    void requireLeft(std::uint64_t bytes, const char* what) {
        if (bytes > left()) {
            corrupt(std::string(what) + " claims " + std::to_string(bytes) + " bytes, but only " +
                    std::to_string(left()) + " remain");
        }
    }

    [[noreturn]] void corrupt(const std::string& problem) const {
        throw InputError(mPath, "corrupt VDB file: " + problem);
    }

    /// OpenVDB reads a fixed-size value as sizeof(T) bytes, whatever its stated size,
    /// so a wrong size leaves every later length read from the wrong place.
    void checkValueSize(const std::string& type, std::uint32_t size) const {
        const std::uint32_t expected = fixedValueSize(type);
        if (expected != 0 && size != expected) {
            corrupt("a '" + type + "' metadata value of " + std::to_string(size) + " bytes (it takes " +
                    std::to_string(expected) + ")");
        }
    }

    static std::uint32_t fixedValueSize(const std::string& type) {
        static const std::map<std::string, std::uint32_t> sizes = {
            {"bool", 1},   {"int32", 4},  {"int64", 8},  {"float", 4},   {"double", 8},  {"vec2i", 8},
            {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12},  {"vec3d", 24},  {"vec4i", 16},
            {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}, {"ptidx32", 4}, {"ptidx64", 8}};
        const auto found = sizes.find(type);
        return found == sizes.end() ? 0 : found->second;
    }

    /// io::DelayedLoadMetadata (the value just skipped) sizes two arrays from a leaf
    /// count and from Blosc headers inside it, none checked against the value's size.
    /// gvr never uses it, so it only has to be harmless: a count the file could hold,
    /// and each array stored raw, or Blosc-compressed to exactly its size, within the
    /// value. Layout: count, then per array a 32-bit stored size (0: raw; for the
    /// second, all ones: absent) and the bytes.
    void checkDelayedLoad(std::uint32_t size) {
        if (size == 0) return;
        const std::streamoff end = mIn.tellg();
        mIn.seekg(-std::streamoff(size), std::ios::cur);
        std::uint64_t budget = size;
        const std::uint32_t count = readWithin<std::uint32_t>(budget);
        if (count > mSize) corrupt("its delayed-load metadata claims more leaf nodes than the file can hold");
        checkDelayedLoadArray(readWithin<std::uint32_t>(budget), count * std::uint64_t(1), budget);  // masks
        const std::uint32_t stored = readWithin<std::uint32_t>(budget);
        if (stored != std::numeric_limits<std::uint32_t>::max()) {
            checkDelayedLoadArray(stored, count * std::uint64_t(8), budget);  // compressed sizes
        }
        mIn.seekg(end);
    }

    void checkDelayedLoadArray(std::uint32_t stored, std::uint64_t rawBytes, std::uint64_t& budget) {
        if (stored == 0) {
            spend(rawBytes, budget);
            mIn.seekg(std::streamoff(rawBytes), std::ios::cur);
            return;
        }
        spend(stored, budget);
        if (stored < 16) corrupt("its delayed-load metadata holds a Blosc block shorter than Blosc's header");
        char header[16];
        mIn.read(header, sizeof header);
        std::uint32_t unpacked = 0, packed = 0;  // Blosc's header: bytes 4-7 and 12-15
        std::memcpy(&unpacked, header + 4, sizeof unpacked);
        std::memcpy(&packed, header + 12, sizeof packed);
        if (unpacked != rawBytes || packed > stored) {
            corrupt("its delayed-load metadata holds a Blosc block of the wrong size");
        }
        mIn.seekg(std::streamoff(stored) - 16, std::ios::cur);
    }

    template <typename T>
    T readWithin(std::uint64_t& budget) {
        spend(sizeof(T), budget);
        return read<T>("delayed-load metadata");
    }

    void spend(std::uint64_t bytes, std::uint64_t& budget) const {
        if (bytes > budget) corrupt("its delayed-load metadata runs past its stated size");
        budget -= bytes;
    }

    const std::string& mPath;
    std::ifstream mIn;
    std::uint64_t mSize = 0;
};

}  // namespace

bool checkVdbLengths(const std::string& path) {
    LengthWalker file(path);
    file.skip(8, "the magic number");
    const std::uint32_t version = file.read<std::uint32_t>("the format version");
    file.skip(8, "the version numbers");  // library major and minor (before 211: the split format version)
    const bool hasOffsets = version < 212 || file.read<char>("the grid-offsets flag") != 0;
    if (version >= openvdb::OPENVDB_FILE_VERSION_SELECTIVE_COMPRESSION &&
        version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) {
        file.skip(1, "the compression flag");
    }
    file.skip(version >= openvdb::OPENVDB_FILE_VERSION_BOOST_UUID ? 36 : 16, "the UUID");
    file.skipMetadata("the file metadata");
    const std::int32_t grids = file.read<std::int32_t>("the grid count");
    if (grids < 0) throw InputError(path, "corrupt VDB file: a negative grid count");
    for (std::int32_t g = 0; g < grids; ++g) {
        file.skipCounted("a grid name");
        file.skipCounted("a grid type name");
        if (version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) file.skipCounted("an instance parent name");
        file.read<std::int64_t>("a grid position");
        file.read<std::int64_t>("a block position");
        const std::int64_t end = file.read<std::int64_t>("a grid end position");
        if (version >= openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) file.skip(4, "a grid compression flag");
        file.skipMetadata("a grid's metadata");
        // From this version the transform follows the metadata; it opens with a map type name.
        if (version >= openvdb::OPENVDB_FILE_VERSION_GRID_INSTANCING) file.skipCounted("a transform's map type");
        if (!hasOffsets) return false;  // the next grid starts after this one's voxels, unknown here
        file.seek(end, "a grid end position");
    }
    return hasOffsets;
}

}  // namespace gvr
