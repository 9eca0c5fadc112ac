/// @file Diagnostics.h
/// @brief gvr's own stderr, kept apart from what libraries print.
///
/// libpng (inside OpenImageIO), nifticlib and GDCM write to file descriptor 2 on
/// their own, which would turn gvr's one-line errors into several lines. At start
/// gvr points descriptor 2 at an unlinked scratch file and writes its own messages,
/// progress bars included, to a duplicate of the original stderr. `--verbose` shows
/// the captured library lines at exit.
#pragma once

#include <cstdio>
#include <ostream>
#include <string>

namespace gvr {

/// Moves library output off the user's stderr. Call once, first thing in main.
void divertLibraryOutput();

/// The user's stderr, for gvr's own messages.
std::ostream& diagnostics();
std::FILE* diagnosticsFile();
int diagnosticsFd();

/// @a message from the library with each setting it names (`nan_to=VALUE`, see
/// SettingNames.h) spelt as a flag: --nan-to VALUE.
std::string inCommandLineTerms(const std::string& message);

/// Prints what the libraries wrote since the diversion, each line prefixed
/// "gvr: library: ", to the user's stderr.
void showLibraryOutput();

}  // namespace gvr
