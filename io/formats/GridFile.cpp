#include "io/formats/GridFile.h"

#include "io/guard/AtomicFile.h"
#include "io/guard/InputFile.h"
#include "io/guard/MemoryBudget.h"
#include "io/guard/VdbLengths.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace gvr {

void initializeOpenVdb() { openvdb::initialize(); }

namespace {

/// OpenVDB reads lengths and counts without checking that the read succeeded, so
/// in a cut file it would size strings and buffers from whatever the variable held
/// (gigabytes on a grid of kilobytes). A stream that throws on the first short read
/// stops it there. io::Stream reads what io::File writes, all in one pass.
openvdb::GridPtrVecPtr streamGrids(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    return stream.getGrids();
}

/// Only the headers, which checkVdbLengths() has walked, so io::File may seek
/// straight to each grid's metadata. A file without grid offsets must be read whole.
openvdb::GridPtrVecPtr gridMetadata(const std::string& path, bool hasGridOffsets) {
    if (hasGridOffsets) {
        openvdb::io::File file(path);
        file.open(/*delayLoad=*/false);
        return file.readAllGridMetadata();
    }
    openvdb::GridPtrVecPtr grids = streamGrids(path);
    for (auto& grid : *grids) grid = grid->copyGridWithNewTree();  // drop the voxels
    return grids;
}

/// Index-to-world must be an invertible affine map with finite entries: the
/// readers, exporters and renderer all invert it. OpenVDB throws only when one
/// asks for the affine map, far from the file.
void checkTransforms(const openvdb::GridPtrVec& grids, const std::string& path) {
    for (const auto& grid : grids) {
        // A frustum's affine part is the identity: read as it, the voxels would move.
        if (!grid->transform().isLinear()) {
            throw InputError(path, "grid '" + grid->getName() +
                                       "' has a non-linear (frustum) transform; "
                                       "gvr reads linear transforms only");
        }
        bool usable = false;
        try {
            const openvdb::Mat4d matrix = grid->transform().baseMap()->getAffineMap()->getMat4();
            usable = std::isfinite(matrix.det());
            for (int i = 0; i < 4; ++i) {
                for (int j = 0; j < 4; ++j) usable = usable && std::isfinite(matrix(i, j));
            }
        } catch (const openvdb::Exception&) {
            usable = false;
        }
        if (!usable) {
            throw InputError(path, "grid '" + grid->getName() + "' has a singular or non-finite transform");
        }
    }
}

/// gvr's metadata sizes what readers allocate (volumeBox), so it is input like a
/// header: dimensions in range, one or three channels, and a positive finite spacing.
void checkVolumeMetadata(const openvdb::GridPtrVec& grids, const std::string& path) {
    for (const auto& grid : grids) {
        const std::optional<VolumeMetadata> metadata = readVolumeMetadata(*grid);
        if (!metadata) continue;
        const std::string where = path + " (grid '" + grid->getName() + "', gvr_dims metadata)";
        checkDimensions(where, {metadata->dims.x(), metadata->dims.y(), metadata->dims.z()});
        if (metadata->channels != 1 && metadata->channels != 3) {
            throw InputError(path, "grid '" + grid->getName() + "' has gvr_channels " +
                                       std::to_string(metadata->channels) + "; gvr writes 1 or 3");
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (!(metadata->spacingMm[axis] > 0.0) || !std::isfinite(metadata->spacingMm[axis])) {
                throw InputError(path, "grid '" + grid->getName() +
                                           "' has a gvr_spacing_mm that is not a "
                                           "positive finite size");
            }
        }
    }
}

/// io::File with delayed loading: each leaf's voxels are read from a memory map of
/// the file when first touched.
openvdb::GridPtrVecPtr mappedGrids(const std::string& path) {
    openvdb::io::File file(path);
    file.setCopyMaxBytes(0);  // map the file itself; OpenVDB would copy one under 500 MB to a temporary
    file.open(/*delayLoad=*/true);
    openvdb::GridPtrVecPtr grids = file.getGrids();
    file.close();  // the grids keep the mapping
    return grids;
}

enum class Voxels { Now, OnDemand, None };

openvdb::GridPtrVecPtr loadGrids(const std::string& path, Voxels voxels, bool hasGridOffsets) {
    switch (voxels) {
        case Voxels::Now:
            return streamGrids(path);
        case Voxels::OnDemand:
            return hasGridOffsets ? mappedGrids(path) : streamGrids(path);
        case Voxels::None:
            return gridMetadata(path, hasGridOffsets);
    }
    return nullptr;
}

openvdb::GridPtrVecPtr readGrids(const std::string& path, Voxels voxels) {
    initializeOpenVdb();
    requireRegularFile(path);
    const bool hasGridOffsets = checkVdbLengths(path);  // the magic number first
    openvdb::GridPtrVecPtr grids;
    try {
        grids = loadGrids(path, voxels, hasGridOffsets);
    } catch (const openvdb::Exception& error) {
        throw InputError(path, std::string("corrupt or truncated VDB file: ") + error.what());
    } catch (const std::ios_base::failure&) {
        throw InputError(path, "truncated or corrupt VDB file: a read ran past its end");
    } catch (const std::bad_alloc&) {
        // Compressed block sizes are 64-bit lengths that OpenVDB allocates before reading.
        throw InputError(path, "corrupt VDB file: a length in it asks for more memory than there is");
    }
    checkTransforms(*grids, path);
    checkVolumeMetadata(*grids, path);
    return grids;
}

bool holdsVolumeValues(const openvdb::GridBase& grid) {
    return grid.isType<openvdb::FloatGrid>() || grid.isType<openvdb::DoubleGrid>() || grid.isType<openvdb::Vec3SGrid>();
}

}  // namespace

openvdb::GridPtrVecPtr readGridFile(const std::string& path) { return readGrids(path, Voxels::Now); }

openvdb::GridPtrVecPtr readGridFileOnDemand(const std::string& path) { return readGrids(path, Voxels::OnDemand); }

openvdb::GridPtrVecPtr readGridMetadataFile(const std::string& path) { return readGrids(path, Voxels::None); }

openvdb::GridBase::Ptr chooseVolumeGrid(const openvdb::GridPtrVec& grids, const std::string& path) {
    // Names and metadata only rank grids of a value type we read: a file may carry an
    // integer grid called "density" (fuzz_vdb found one), or gvr's metadata on a mask.
    openvdb::GridPtrVec candidates;
    for (const auto& grid : grids) {
        if (holdsVolumeValues(*grid)) candidates.push_back(grid);
    }
    // gvr marks its volume with metadata, so an RGB export's colour wins over the density derived from it.
    for (const auto& grid : candidates) {
        if (readVolumeMetadata(*grid)) return grid;
    }
    for (const char* name : {"density", "color", "Cd"}) {
        for (const auto& grid : candidates) {
            if (grid->getName() == name) return grid;
        }
    }
    if (!candidates.empty()) return candidates.front();
    std::string found;
    for (const auto& grid : grids) found += " " + grid->getName() + " (" + grid->valueType() + ")";
    throw InputError(
        path, "holds no float, double or Vec3s grid; found:" + (found.empty() ? std::string(" nothing") : found));
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
