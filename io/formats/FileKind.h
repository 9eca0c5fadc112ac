/// @file FileKind.h
/// @brief What a file is, decided in one place from its content and its name: which
/// reader an input gets, and which writer an output gets.
#pragma once

#include <string>

namespace gvr {

/// What an input path holds.
enum class FileKind {
    Asset,      ///< a Gaussian asset (GVRASSET magic), whatever its name
    Vdb,        ///< an OpenVDB file (its magic number), whatever its name
    Nifti,      ///< .nii, .nii.gz
    Mgh,        ///< .mgh, .mgz
    MetaImage,  ///< .mha, .mhd
    Image,      ///< a 2D image: .png, .tif, .tiff, .jpg, .jpeg, .bmp, .exr
    Folder,     ///< a DICOM series or an image stack
    Other,      ///< none of these (raw data, a missing file, a FIFO, a .vdb without the magic)
};

/// The kind from the name alone, for files listed in a folder: never Asset or
/// Folder; Vdb for the .vdb extension, Other for a name no reader claims.
FileKind fileKindByName(const std::string& path);

/// The kind of @a path: a folder, else the magic numbers of an asset and of OpenVDB
/// (read from regular files only: a FIFO would block the read), else the name.
FileKind fileKind(const std::string& path);

/// What an output path asks to be written as, by its extension.
enum class OutputFormat { Vdb, Nifti, Png, Exr, Other };

OutputFormat outputFormat(const std::string& path);

}  // namespace gvr
