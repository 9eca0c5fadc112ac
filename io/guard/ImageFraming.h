/// @file ImageFraming.h
/// @brief Checks that a PNG, JPEG, BMP or TIFF slice is whole, before OpenImageIO decodes it.
///
/// libjpeg decodes a cut-off JPEG with a warning only, filling the rest with grey,
/// and OpenImageIO passes it on as a success. libpng reports a damaged PNG through
/// a longjmp that skips OpenImageIO's destructors (a leak per bad file, and
/// libpng's own line on stderr). Both formats frame their data well enough to tell
/// a whole file from a damaged one cheaply.
#pragma once

#include <string>

namespace gvr {

/// A PNG (by its signature) must be a chain of chunks whose CRC-32s hold, up to
/// IEND; a JPEG (by its SOI marker) must end with its end-of-image marker; a BMP
/// ("BM") must be uncompressed, of a standard depth, and hold every row; a TIFF
/// must hold every page and strip its directories name. Other files pass unchecked.
/// @throw InputError naming @a file for a cut or damaged PNG, a cut JPEG, a BMP
///        that is compressed, cut or corrupt, or a TIFF cut short (io/guard/TiffFraming.h).
void checkImageFraming(const std::string& file);

}  // namespace gvr
