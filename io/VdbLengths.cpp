#include "VdbLengths.h"

#include "Error.h"

#include <openvdb/version.h>

#include <cstdint>
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
        if (bytes > left()) {
            throw InputError(mPath, "corrupt VDB file: " + std::string(what) + " claims " + std::to_string(bytes) +
                                        " bytes, but only " + std::to_string(left()) + " remain");
        }
        mIn.seekg(std::streamoff(bytes), std::ios::cur);
    }

    /// A 32-bit length followed by that many bytes: strings and metadata values.
    void skipCounted(const char* what) { skip(read<std::uint32_t>(what), what); }

    /// MetaMap: a count, then per entry a name, a type name and a sized value.
    void skipMetadata(const char* what) {
        const std::uint32_t count = read<std::uint32_t>(what);
        if (count > left() / 12) {  // each entry holds at least three 4-byte lengths
            throw InputError(mPath, "corrupt VDB file: " + std::string(what) + " claims " + std::to_string(count) +
                                        " entries, more than the file can hold");
        }
        for (std::uint32_t k = 0; k < count; ++k) {
            skipCounted("a metadata name");
            skipCounted("a metadata type name");
            skipCounted("a metadata value");
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
        if (!hasOffsets) return false;  // the next grid starts after this one's voxels, unknown here
        file.seek(end, "a grid end position");
    }
    return hasOffsets;
}

}  // namespace gvr
