#include "io/guard/VdbLengths.h"

#include "io/guard/ByteOrder.h"
#include "pipeline/Error.h"

#include <openvdb/Exceptions.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/io.h>
#include <openvdb/math/Transform.h>
#include <openvdb/points/StreamCompression.h>
#include <openvdb/version.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
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
        char bytes[sizeof(T)];
        mIn.read(bytes, sizeof bytes);
        if (!mIn) throw InputError(mPath, std::string("truncated VDB file: it ends inside ") + what);
        return loadLittleEndian<T>(bytes);
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

    /// Whether the file begins with OpenVDB's magic number, written as 64 bits; reads past it.
    bool readMagic() {
        if (left() < 8) return false;
        const std::int32_t magic = read<std::int32_t>("the magic number");
        skip(4, "the magic number");
        return magic == openvdb::OPENVDB_MAGIC;
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
    /// and each array stored raw, or Blosc-compressed to its size (or to the padding
    /// OpenVDB gives short arrays), within the
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
        // OpenVDB pads arrays shorter than BLOSC_PAD_BYTES before compressing them,
        // and reserves what the header says.
        const std::uint64_t padded = std::max<std::uint64_t>(rawBytes, openvdb::compression::BLOSC_PAD_BYTES);
        if (unpacked < rawBytes || unpacked > padded || packed > stored) {
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

public:
    /// The tree of a grid whose type walkTree() knows: Tree_<value>_5_4_3, values
    /// stored as 16-bit halves when the type name ends in _HalfFloat.
    struct TreeType {
        std::uint32_t valueBytes = 0;   ///< 0: a type this walker does not know
        std::uint32_t storedBytes = 0;  ///< per value in compressed blocks
    };

    static TreeType treeType(const std::string& gridType) {
        static const std::map<std::string, std::pair<std::uint32_t, std::uint32_t>> types = {
            {"float", {4, 2}}, {"double", {8, 2}}, {"vec3s", {12, 6}}, {"vec3d", {24, 6}},
            {"int32", {4, 4}}, {"int64", {8, 8}},  {"vec3i", {12, 12}}};
        const std::string prefix = "Tree_", suffix = "_5_4_3", half = "_HalfFloat";
        std::string name = gridType;
        const bool isHalf =
            name.size() > half.size() && name.compare(name.size() - half.size(), half.size(), half) == 0;
        if (isHalf) name.resize(name.size() - half.size());
        if (name.rfind(prefix, 0) != 0 || name.size() < prefix.size() + suffix.size() ||
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
            return {};
        }
        const auto found = types.find(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()));
        if (found == types.end()) return {};
        return {found->second.first, isHalf ? found->second.second : found->second.first};
    }

    /// The transform: a map type name, then what that map stores, which OpenVDB
    /// reads as fixed-size fields once the name's length is known to be sane.
    void skipTransform(std::uint32_t version, std::uint32_t libraryMajor, std::uint32_t libraryMinor) {
        const std::uint32_t length = read<std::uint32_t>("a transform's map type");
        requireLeft(length, "a transform's map type");
        mIn.seekg(-4, std::ios::cur);
        openvdb::io::setVersion(mIn, openvdb::VersionId(libraryMajor, libraryMinor), version);
        try {
            openvdb::math::Transform().read(mIn);
        } catch (const openvdb::Exception& error) {
            corrupt(std::string("its transform: ") + error.what());
        }
        if (!mIn) throw InputError(mPath, "truncated VDB file: it ends inside a transform");
    }

    /// Topology, then every leaf's voxel block, as Tree::readTopology() and
    /// Tree::readBuffers() read them. Each compressed block is checked against the
    /// size OpenVDB will decode it into: Debian's OpenVDB 10 reads an uncompressed
    /// block of whatever size the file states into a buffer of the expected size.
    void walkTree(const TreeType& tree, std::uint32_t compression) {
        mCompression = compression;
        mTree = tree;
        std::uint64_t leaves = 0;
        if (read<std::int32_t>("a tree's buffer count") != 1) corrupt("a tree with other than one buffer");
        skip(tree.valueBytes, "a tree's background value");
        const std::uint32_t tiles = read<std::uint32_t>("a root node's tile count");
        const std::uint32_t children = read<std::uint32_t>("a root node's child count");
        for (std::uint32_t t = 0; t < tiles; ++t) skip(12 + tree.valueBytes + 1, "a root node's tile");
        for (std::uint32_t c = 0; c < children; ++c) {
            skip(12, "a root node child's origin");
            leaves += walkInternalTopology(5);
        }
        for (std::uint64_t leaf = 0; leaf < leaves; ++leaf) {
            const std::uint32_t active = readMaskCount(3);
            walkCompressedValues(512, active);
        }
    }

private:
    /// Reads a node mask of 2^(3 log2Dim) bits and returns how many are set.
    std::uint32_t readMaskCount(int log2Dim) {
        std::uint32_t count = 0;
        for (std::uint32_t word = 0; word < (1u << (3 * log2Dim)) / 64; ++word) {
            count += std::uint32_t(__builtin_popcountll(read<std::uint64_t>("a node mask")));
        }
        return count;
    }

    /// An internal node of 2^(3 log2Dim) entries and, below it, its children's
    /// topology; returns the number of leaves under it.
    std::uint64_t walkInternalTopology(int log2Dim) {
        const std::uint32_t children = readMaskCount(log2Dim);
        const std::uint32_t active = readMaskCount(log2Dim);
        walkCompressedValues(1u << (3 * log2Dim), active);
        if (log2Dim == 4) {
            skip(std::uint64_t(children) * 64, "the leaf masks of a node");
            return children;
        }
        std::uint64_t leaves = 0;
        for (std::uint32_t c = 0; c < children; ++c) leaves += walkInternalTopology(4);
        return leaves;
    }

    /// io::readCompressedValues(): a flag byte, up to two inactive values, maybe a
    /// selection mask, then all @a count values or only the @a active ones.
    void walkCompressedValues(std::uint32_t count, std::uint32_t active) {
        enum : std::int8_t {
            kOneInactive = 2,
            kMaskNoInactive = 3,
            kMaskOneInactive = 4,
            kMaskTwoInactive = 5,
            kAllValues = 6
        };
        const std::int8_t flag = read<std::int8_t>("a compressed block's flag");
        if (flag == kOneInactive || flag == kMaskOneInactive || flag == kMaskTwoInactive) {
            skip(mTree.valueBytes, "an inactive value");
        }
        if (flag == kMaskTwoInactive) skip(mTree.valueBytes, "an inactive value");
        if (flag == kMaskNoInactive || flag == kMaskOneInactive || flag == kMaskTwoInactive) {
            skip(count / 8, "a selection mask");
        }
        const bool onlyActive = (mCompression & openvdb::io::COMPRESS_ACTIVE_MASK) && flag != kAllValues;
        const std::uint32_t stored = onlyActive ? active : count;
        if (stored == 0 && mTree.storedBytes != mTree.valueBytes) return;  // io::HalfReader reads no empty block
        walkBlock(std::uint64_t(stored) * mTree.storedBytes);
    }

    /// One block of @a bytes values, as io::readData() reads it.
    void walkBlock(std::uint64_t bytes) {
        if (!(mCompression & (openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ZIP))) {
            skip(bytes, "a voxel block");
            return;
        }
        const std::int64_t stored = read<std::int64_t>("a compressed block's size");
        if (stored <= 0) {                                           // stored uncompressed
            const std::uint64_t stated = 0 - std::uint64_t(stored);  // -stored, even for INT64_MIN
            if (stated != bytes) {
                corrupt("an uncompressed block of " + std::to_string(stated) + " bytes where " + std::to_string(bytes) +
                        " belong");
            }
            skip(bytes, "a voxel block");
            return;
        }
        requireLeft(std::uint64_t(stored), "a compressed block");
        if (mCompression & openvdb::io::COMPRESS_BLOSC) checkBloscHeader(std::uint64_t(stored), bytes);
        skip(std::uint64_t(stored), "a compressed block");
    }

    /// Blosc reads its 16-byte header, and then as many bytes as the header says,
    /// from a buffer of the size the file states.
    void checkBloscHeader(std::uint64_t stored, std::uint64_t bytes) {
        if (stored < 16) corrupt("a Blosc block shorter than Blosc's header");
        char header[16];
        mIn.read(header, sizeof header);
        mIn.seekg(-16, std::ios::cur);
        std::uint32_t unpacked = 0, packed = 0;  // bytes 4-7 and 12-15
        std::memcpy(&unpacked, header + 4, sizeof unpacked);
        std::memcpy(&packed, header + 12, sizeof packed);
        if (unpacked != bytes || packed > stored) corrupt("a Blosc block whose header does not match its size");
    }

    std::uint32_t mCompression = 0;
    TreeType mTree;
    const std::string& mPath;
    std::ifstream mIn;
    std::uint64_t mSize = 0;
};

}  // namespace

bool checkVdbLengths(const std::string& path) {
    LengthWalker file(path);
    if (!file.readMagic()) throw InputError(path, "not a VDB file (no OpenVDB magic number)");
    const std::uint32_t version = file.read<std::uint32_t>("the format version");
    if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION || version > openvdb::OPENVDB_FILE_VERSION) {
        throw InputError(path, "VDB format version " + std::to_string(version) + " (gvr reads " +
                                   std::to_string(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) + " to " +
                                   std::to_string(openvdb::OPENVDB_FILE_VERSION) + ": OpenVDB 3.0, 2014, and later)");
    }
    const std::uint32_t libraryMajor = file.read<std::uint32_t>("the library version");
    const std::uint32_t libraryMinor = file.read<std::uint32_t>("the library version");
    const bool hasOffsets = file.read<char>("the grid-offsets flag") != 0;
    file.skip(36, "the UUID");
    file.skipMetadata("the file metadata");
    const std::int32_t grids = file.read<std::int32_t>("the grid count");
    if (grids < 0) throw InputError(path, "corrupt VDB file: a negative grid count");
    for (std::int32_t g = 0; g < grids; ++g) {
        const std::string name = file.readCounted("a grid name");
        const std::string type = file.readCounted("a grid type name");
        const bool isInstance = !file.readCounted("an instance parent name").empty();
        file.read<std::int64_t>("a grid position");
        file.read<std::int64_t>("a block position");
        const std::int64_t end = file.read<std::int64_t>("a grid end position");
        const std::uint32_t compression = file.read<std::uint32_t>("a grid compression flag");
        file.skipMetadata("a grid's metadata");
        file.skipTransform(version, libraryMajor, libraryMinor);
        if (isInstance) continue;  // it shares another grid's tree and stores none
        const LengthWalker::TreeType tree = LengthWalker::treeType(type);
        if (tree.valueBytes == 0) {
            throw InputError(path, "grid '" + name + "' is a " + type + ", a type gvr does not read");
        }
        file.walkTree(tree, compression);
        if (hasOffsets) file.seek(end, "a grid end position");
    }
    return hasOffsets;
}

}  // namespace gvr
