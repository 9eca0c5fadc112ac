/// @file Ingest.h
/// @brief Any supported source volume to a sparse grid in physical units.
#pragma once

#include "GridBuilder.h"
#include "Readers.h"

namespace gvr {

struct IngestOptions {
    ReadOptions read;
    GridBuildSettings build;  ///< sourceFile is filled in from the input path
    ProgressFn buildProgress;  ///< the reading phase reports through read.progress
};

struct IngestResult {
    openvdb::GridBase::Ptr grid;
    std::vector<std::string> warnings;
};

IngestResult ingest(const std::string& input, IngestOptions options);

/// The volume grid of a .vdb file as it is, or any other input ingested with @a options.
IngestResult loadOrIngest(const std::string& input, const IngestOptions& options);

}  // namespace gvr
