#include "io/formats/VolumeOutputs.h"

#include "io/DenseCopy.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/guard/AtomicFile.h"
#include "io/guard/InputFile.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

#include <filesystem>

namespace gvr {

namespace {

/// Writes @a path's file at @a staging.
WrittenVolume writeOne(const std::string& path, const std::string& staging, const openvdb::GridCPtrVec& grids,
                       const openvdb::CoordBBox& box, const NiftiStorage& storage) {
    WrittenVolume written{path, volumeFileFormat(path)};
    if (written.format == VolumeFileFormat::Vdb) {
        writeGridFile(staging, grids);
    } else {
        written.clampedSamples = writeNifti(staging, denseCopy(*grids.front(), box, path, "write NIfTI"), storage);
    }
    written.fileBytes = std::filesystem::file_size(staging);
    return written;
}

}  // namespace

VolumeFileFormat volumeFileFormat(const std::string& path) {
    switch (outputFormat(path)) {
        case OutputFormat::Vdb:
            return VolumeFileFormat::Vdb;
        case OutputFormat::Nifti:
            return VolumeFileFormat::Nifti;
        default:
            break;
    }
    throw InputError(path, "unknown output extension: use .vdb (OpenVDB), .nii or .nii.gz (NIfTI)");
}

NiftiStorage ingestedNiftiStorage(const openvdb::GridBase& grid, bool float32) {
    const std::optional<VolumeMetadata> metadata = readVolumeMetadata(grid);
    return niftiStorageLike(metadata.value_or(VolumeMetadata{}), float32 || !metadata);
}

void checkVolumeOutputs(const std::string& flag, const std::vector<std::string>& outputs,
                        const std::vector<std::string>& inputs) {
    if (outputs.empty()) throw InputError(flag, "an output file is required");
    bool seen[2] = {false, false};
    for (const std::string& output : outputs) {
        requireNoNulByte(output);  // before its extension, which a NUL byte hides
        const int format = int(volumeFileFormat(output));
        if (seen[format]) {
            throw InputError(
                flag, "two outputs of the same format (" + output + "): give at most one .vdb and one .nii/.nii.gz");
        }
        seen[format] = true;
        checkOutputPath(flag, output, inputs);
    }
}

std::vector<WrittenVolume> writeVolumeOutputs(const std::vector<std::string>& outputs,
                                              const openvdb::GridCPtrVec& grids, const openvdb::CoordBBox& box,
                                              const NiftiStorage& storage) {
    // Staged, then renamed together: a failure of the second output once deleted
    // the first after it had replaced the user's older file of that name.
    std::vector<WrittenVolume> written;
    std::vector<std::function<void(const std::string&)>> writes;
    for (const std::string& path : outputs) {
        writes.push_back(
            [&, path](const std::string& staging) { written.push_back(writeOne(path, staging, grids, box, storage)); });
    }
    writeAllOrNone(outputs, writes);
    return written;
}

}  // namespace gvr
