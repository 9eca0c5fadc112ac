/// @file SampleFile.h
/// @brief Reads a block of voxel samples that follows a header, plain or deflated.
#pragma once

#include "io/DenseVolume.h"

#include <cstdint>
#include <string>

namespace gvr {

/// Reads volume.samples (dims, channels and type already set, and checked against
/// memory with reserveSamples()) from @a file at @a offset and converts them to
/// host byte order. These readers size the buffer themselves, as the bytes arrive
/// or after checking the file's size, so that a header that claims more than the
/// file holds costs no memory.
/// @throw InputError naming @a file when it holds fewer bytes than the volume needs,
///        or when compressed data fails its CRC or Adler-32 check.
void readPlainSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume);

/// As readPlainSamples, for a file that may be gzip'd as a whole (.nii.gz, .mgz);
/// @a offset counts bytes of the uncompressed stream.
void readGzipSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume);

/// As readPlainSamples, for a zlib or gzip stream starting at @a offset.
void readDeflatedSamples(const std::string& file, std::uint64_t offset, bool bigEndian, DenseVolume& volume);

}  // namespace gvr
