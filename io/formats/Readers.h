/// @file Readers.h
/// @brief Decoders for the volume formats gvr ingests, one per source file.
///
/// Every reader validates its header before it allocates, throws InputError naming
/// the file on anything truncated, corrupt or unsupported, and returns physical
/// values through DenseVolume::slope and intercept. World coordinates are RAS
/// millimetres (NIfTI's convention); LPS formats (DICOM, MetaImage) are flipped.
#pragma once

#include "io/DenseVolume.h"
#include "io/formats/SliceSource.h"
#include "pipeline/Progress.h"

#include <openvdb/Types.h>

#include <memory>
#include <optional>
#include <string>

namespace gvr {

/// How to read a headerless raw file (--raw-dims, --raw-type, --endian, --header-bytes).
struct RawLayout {
    std::array<std::int64_t, 3> dims{0, 0, 0};
    SampleType type = SampleType::UInt8;
    int channels = 1;
    bool bigEndian = false;
    std::uint64_t headerBytes = 0;
};

struct ReadOptions {
    int volumeIndex = 0;  ///< which 3D volume of a 4D file (--volume)
    /// Voxel size in mm for formats that do not store one (stacks, raw).
    std::optional<openvdb::Vec3d> spacingMm;
    std::optional<RawLayout> raw;  ///< set: read INPUT as raw samples
    /// A header may name its data file (MetaImage's ElementDataFile). Unless this is
    /// set, that file must lie in the header's folder or below it, so that a header
    /// from elsewhere cannot make gvr read, say, ../../etc/passwd into a grid.
    bool dataFilesAnywhere = false;
    ProgressFn progress;
};

DenseVolume readNifti(const std::string& path, const ReadOptions& options);
/// True when @a path carries the DICOM Part 10 magic ("DICM" after the preamble).
bool isDicomFile(const std::string& path);
DenseVolume readMetaImage(const std::string& path, const ReadOptions& options);
DenseVolume readMgh(const std::string& path, const ReadOptions& options);
DenseVolume readVdb(const std::string& path, const ReadOptions& options);

/// Picks the reader for @a input: a file, a folder (DICOM series or image stack) or a
/// glob pattern of images, and reads the whole volume.
DenseVolume readVolume(const std::string& input, const ReadOptions& options);

/// The files reading @a input opens: a pattern's matches, a folder's images and
/// DICOM files, a MetaImage header and its data file, else @a input itself. No
/// output may be one of them.
std::vector<std::string> filesReadFrom(const std::string& input);

/// The file that holds a MetaImage's samples: the header itself for LOCAL.
/// @throw InputError naming @a path for a corrupt header or a slice list.
std::string metaImageDataFile(const std::string& path);

/// The slab-by-slab source for @a input when its format can stream (raw files,
/// image stacks, DICOM series; see SliceSource.h), else null.
/// @throw InputError naming the input when it does not exist or its headers are bad.
std::unique_ptr<SliceSource> openSliceSource(const std::string& input, const ReadOptions& options);

/// For formats that carry no geometry: axis-aligned voxels of --spacing, or of
/// 1 mm with a warning when none was given.
void setGivenSpacing(const ReadOptions& options, DenseVolume& volume);

}  // namespace gvr
