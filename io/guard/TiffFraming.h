/// @file TiffFraming.h
/// @brief Checks that a TIFF holds every page and every strip or tile its directories promise.
///
/// libtiff ends a page chain quietly at a directory past the end of the file, so
/// OpenImageIO gives a multi-page TIFF cut short as a shorter stack with no error.
/// The directories name every page and where its pixels lie, so a cut file can be
/// told from a whole one by reading them alone.
#pragma once

#include <cstdint>
#include <istream>
#include <string>

namespace gvr {

/// True when @a head (at least 4 bytes) starts as a classic or BigTIFF file does, in either byte order.
bool isTiffSignature(const std::string& head);

/// Walks the chain of page directories of the TIFF @a in (of @a size bytes) and the
/// strip or tile extents each directory lists.
/// @throw InputError naming @a file when a directory or a page's pixel data lies past
///        the end of the file, or the chain loops.
void checkTiffFraming(const std::string& file, std::istream& in, std::uint64_t size);

}  // namespace gvr
