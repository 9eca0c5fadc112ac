/// @file GridFile.h
/// @brief Reading and writing .vdb files.
#pragma once

#include <openvdb/openvdb.h>

#include <string>

namespace gvr {

/// Registers OpenVDB's types; safe to call many times from one thread.
void initializeOpenVdb();

/// @throw InputError naming @a path when it is missing, truncated or not a VDB file.
openvdb::GridPtrVecPtr readGridFile(const std::string& path);

/// As readGridFile, but each leaf's voxels stay in the file until first touched
/// (OpenVDB's delayed loading, from a memory map): a process that uses part of a
/// large grid, such as an MPI rank fitting some of its bricks, reads only that
/// part. The file must stay unchanged while the grids are in use. Every length in
/// it is checked first, as readGridFile does. A file written without grid offsets
/// is read whole.
openvdb::GridPtrVecPtr readGridFileOnDemand(const std::string& path);

/// The grids of @a path with their metadata and transforms but no voxels: cheap
/// however large the file. @throw InputError as readGridFile.
openvdb::GridPtrVecPtr readGridMetadataFile(const std::string& path);

/// The volume grid of a file: the grid carrying gvr's VolumeMetadata (what ingest
/// and export write), else "density", "color" or "Cd", then the first
/// float, double or Vec3s grid. @throw InputError naming @a path when there is none.
openvdb::GridBase::Ptr chooseVolumeGrid(const openvdb::GridPtrVec& grids, const std::string& path);

/// Writes @a grids with Blosc compression, atomically (see writeAtomically).
void writeGridFile(const std::string& path, const openvdb::GridCPtrVec& grids);

}  // namespace gvr
