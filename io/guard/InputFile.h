/// @file InputFile.h
/// @brief What gvr may open as an input: regular files only. A FIFO waits forever
/// for a writer and a device such as /dev/zero never ends, and the libraries that
/// open paths themselves (nifticlib, GDCM, OpenImageIO) would do either.
#pragma once

#include <string>

namespace gvr {

/// @throw InputError naming @a path when it does not exist or is not a regular
/// file (links followed): a folder, a FIFO, a socket or a device.
void requireRegularFile(const std::string& path);

/// @throw InputError when @a path holds a NUL byte: the system would read it only
/// up to there (Python strings may carry one).
void requireNoNulByte(const std::string& path);

}  // namespace gvr
