/// @file LabelGrid.h
/// @brief Structure labels stored beside the intensity grid: an Int32 grid named
/// "labels" on the same voxels, with the structures' names as grid metadata.
#pragma once

#include "io/formats/Readers.h"
#include "pipeline/LabelTable.h"

#include <openvdb/openvdb.h>

#include <string>

namespace gvr {

constexpr const char* kLabelGridName = "labels";

/// One structure per line, "ID NAME [anything else]": AAL's .txt and FreeSurfer's
/// colour LUT both read. '#' starts a comment. @throw InputError naming @a path and
/// the line for anything else.
LabelTable readLabelNames(const std::string& path);

struct LabelGridSettings {
    LabelTable names;       ///< from --label-names; unnamed labels become "label_<id>"
    bool resample = false;  ///< a different lattice is resampled (nearest neighbour), not refused
};

/// Reads the label volume @a path (any format ingest reads) onto the voxels of
/// @a image, a grid from ingest. Voxels with label 0 stay inactive.
/// @throw InputError naming @a path when its samples are not integers, or when its
///        dimensions or placement differ from the image's and !settings.resample.
openvdb::Int32Grid::Ptr buildLabelGrid(const std::string& path, const ReadOptions& options,
                                       const openvdb::GridBase& image, const LabelGridSettings& settings);

/// The names stored on a label grid.
LabelTable labelTableOf(const openvdb::GridBase& labels);

/// The label grid among @a grids; null when there is none.
openvdb::Int32Grid::Ptr storedLabelGrid(const openvdb::GridPtrVec& grids);

/// The label grid among @a grids. @throw InputError naming @a path when there is none.
openvdb::Int32Grid::Ptr findLabelGrid(const openvdb::GridPtrVec& grids, const std::string& path);

}  // namespace gvr
