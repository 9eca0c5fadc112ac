/// @file VolumeOutputs.h
/// @brief Where a reconstruction or an ingested volume goes: one file per `-o`,
/// in the format its extension names, all written or none.
#pragma once

#include "io/formats/NiftiWriter.h"

#include <openvdb/openvdb.h>

#include <cstdint>
#include <string>
#include <vector>

namespace gvr {

enum class VolumeFileFormat { Vdb, Nifti };

/// The format @a path's extension names: .vdb, or .nii or .nii.gz (any case).
/// @throw InputError naming @a path for any other extension.
VolumeFileFormat volumeFileFormat(const std::string& path);

/// Checks a command's outputs before any work: at least one, each with a known
/// extension, one per format, and each writable without touching @a inputs
/// (see checkOutputPath). @throw InputError naming @a flag or the path at fault.
void checkVolumeOutputs(const std::string& flag, const std::vector<std::string>& outputs,
                        const std::vector<std::string>& inputs);

struct WrittenVolume {
    std::string path;
    VolumeFileFormat format = VolumeFileFormat::Vdb;
    std::uint64_t fileBytes = 0;
    std::uint64_t clampedSamples = 0;  ///< NIfTI: samples clamped into its datatype
};

/// How `gvr ingest` stores @a grid (an ingested volume) as NIfTI: in the source's
/// sample type and scaling, or float32 when @a float32 asks for it or the grid
/// records no source.
NiftiStorage ingestedNiftiStorage(const openvdb::GridBase& grid, bool float32);

/// Writes each of @a outputs: all of @a grids as OpenVDB, or the first of them over
/// @a box as NIfTI stored as @a storage says. If one write fails, the files already
/// written are removed before the error goes on.
std::vector<WrittenVolume> writeVolumeOutputs(const std::vector<std::string>& outputs,
                                              const openvdb::GridCPtrVec& grids, const openvdb::CoordBBox& box,
                                              const NiftiStorage& storage);

}  // namespace gvr
