/// @file ImageFile.h
/// @brief Rendered frames out through OpenImageIO.
#pragma once

#include <string>

namespace gvr {

/// Writes a width x height RGBA image of premultiplied floats (rows top to bottom)
/// atomically. The extension picks the format: .png as 8-bit RGBA with straight
/// alpha (what viewers expect of PNG), .exr as 32-bit float RGBA, premultiplied (the
/// EXR convention).
/// @throw InputError naming @a path for another extension or a failed write.
void writeImage(const std::string& path, int width, int height, const float* premultipliedRgba);

}  // namespace gvr
