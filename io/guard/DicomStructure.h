/// @file DicomStructure.h
/// @brief Checks that a DICOM file's elements lie inside it, before GDCM reads it.
///
/// GDCM asserts, and so aborts the whole process, on a file cut inside its header
/// or inside its compressed pixel data's fragments.
/// Walking the element structure first turns those files into a one-line error.
#pragma once

#include <string>

namespace gvr {

/// Walks the file meta information and the data set up to and including the
/// pixel data: every element, item, nested sequence and compressed fragment must
/// end inside the file (and inside its parent), and compressed pixel data must
/// end with its delimiter. Native pixel data may be short (the reader says by how
/// much). Deflated data sets are only checked up to their meta information.
/// @throw InputError naming @a file when an element runs past the end.
void checkDicomStructure(const std::string& file);

}  // namespace gvr
