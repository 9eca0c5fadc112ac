#include "GridFile.h"

#include "AtomicFile.h"
#include "Error.h"
#include "VolumeMetadata.h"

#include <filesystem>
#include <fstream>

namespace gvr {

void initializeOpenVdb() { openvdb::initialize(); }

bool isVdbFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::int32_t magic = 0;
    in.read(reinterpret_cast<char*>(&magic), sizeof magic);
    return in && magic == openvdb::OPENVDB_MAGIC;
}

namespace {

openvdb::GridPtrVecPtr readGrids(const std::string& path, bool voxels) {
    initializeOpenVdb();
    if (!std::filesystem::exists(path)) throw InputError(path, "no such file");
    if (!isVdbFile(path)) throw InputError(path, "not a VDB file (no OpenVDB magic number)");
    try {
        openvdb::io::File file(path);
        file.open(/*delayLoad=*/false);
        openvdb::GridPtrVecPtr grids = voxels ? file.getGrids() : file.readAllGridMetadata();
        file.close();
        return grids;
    } catch (const openvdb::Exception& error) {
        throw InputError(path, std::string("corrupt or truncated VDB file: ") + error.what());
    } catch (const std::ios_base::failure& error) {
        throw InputError(path, std::string("truncated VDB file: ") + error.what());
    }
}

}  // namespace

openvdb::GridPtrVecPtr readGridFile(const std::string& path) { return readGrids(path, /*voxels=*/true); }

openvdb::GridPtrVecPtr readGridMetadataFile(const std::string& path) { return readGrids(path, /*voxels=*/false); }

openvdb::GridBase::Ptr chooseVolumeGrid(const openvdb::GridPtrVec& grids, const std::string& path) {
    // gvr marks its volume with metadata, so an RGB export's colour wins over the density derived from it.
    for (const auto& grid : grids) {
        if (readVolumeMetadata(*grid)) return grid;
    }
    for (const char* name : {"density", "color", "Cd"}) {
        for (const auto& grid : grids) {
            if (grid->getName() == name) return grid;
        }
    }
    for (const auto& grid : grids) {
        if (grid->isType<openvdb::FloatGrid>() || grid->isType<openvdb::DoubleGrid>() ||
            grid->isType<openvdb::Vec3SGrid>()) {
            return grid;
        }
    }
    std::string found;
    for (const auto& grid : grids) found += " " + grid->getName() + " (" + grid->valueType() + ")";
    throw InputError(path, "holds no float, double or Vec3s grid; found:" +
                               (found.empty() ? std::string(" nothing") : found));
}

namespace {

/// Writes what io::File writes (a seekable archive), but into a stream whose
/// state we check afterwards: io::File ignores write errors, so a full disk or
/// ulimit -f would leave a cut file that looks written.
class CheckedFileArchive : public openvdb::io::Archive {
public:
    void writeTo(const std::string& path, const std::string& culprit, const openvdb::GridCPtrVec& grids) const {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError(culprit, "cannot open the file for writing");
        Archive::write(out, grids, /*seekable=*/true);
        out.close();
        if (!out) throw InputError(culprit, "writing failed (disk full or file size limit?)");
    }
};

}  // namespace

void writeGridFile(const std::string& path, const openvdb::GridCPtrVec& grids) {
    initializeOpenVdb();
    writeAtomically(path, [&](const std::string& temporary) {
        CheckedFileArchive archive;
        archive.setCompression(openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK);
        archive.writeTo(temporary, path, grids);
    });
}

}  // namespace gvr
