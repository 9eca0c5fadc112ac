/// @file Ingest.h
/// @brief Any supported source volume to a sparse grid in physical units.
#pragma once

#include "io/GridBuilder.h"
#include "io/formats/Readers.h"

namespace gvr {

struct IngestOptions {
    ReadOptions read;
    GridBuildSettings build;   ///< sourceFile is filled in from the input path
    ProgressFn buildProgress;  ///< the reading phase reports through read.progress
    /// A label volume (an atlas such as aal.nii.gz, any format ingest reads) to place
    /// on the image's voxels, as `gvr ingest --labels` does.
    std::string labels;
    std::string labelNames;       ///< "ID NAME" lines naming the atlas's labels
    bool resampleLabels = false;  ///< an atlas on another lattice is resampled, not refused
    /// loadGridFile() and loadOrIngest(): a .vdb's voxels are read when first touched (readGridFileOnDemand).
    bool vdbOnDemand = false;
};

struct IngestResult {
    openvdb::GridBase::Ptr grid;
    /// options.labels placed on @a grid, or the label grid that a .vdb from
    /// `ingest --labels` holds; else null.
    openvdb::Int32Grid::Ptr labels;
    std::vector<std::string> warnings;
};

/// @throw InputError naming the input, or the label volume, at fault.
IngestResult ingest(const std::string& input, IngestOptions options);

/// The volume grid of a .vdb file as it is, with the label grid it holds, or with
/// options.labels placed on it; a file that is not a .vdb is refused.
IngestResult loadGridFile(const std::string& path, const IngestOptions& options);

/// loadGridFile() for a .vdb file, else the input ingested with @a options.
IngestResult loadOrIngest(const std::string& input, const IngestOptions& options);

/// The label volume options.labels (its first volume) placed on @a image's voxels
/// and named from options.labelNames.
/// @throw InputError naming the label volume or the names file.
openvdb::Int32Grid::Ptr readLabels(const IngestOptions& options, const openvdb::GridBase& image);

}  // namespace gvr
