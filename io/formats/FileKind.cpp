#include "io/formats/FileKind.h"

#include "io/asset/AssetFile.h"
#include "pipeline/LowerCase.h"

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>

namespace gvr {

namespace {

bool endsWithAny(const std::string& path, std::initializer_list<const char*> extensions) {
    return std::any_of(extensions.begin(), extensions.end(),
                       [&](const char* extension) { return endsWithIgnoringCase(path, extension); });
}

/// The file's first bytes, as many as the longer magic.
std::string leadingBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string bytes(std::max(sizeof kAssetMagic, sizeof(std::int32_t)), '\0');
    in.read(bytes.data(), std::streamsize(bytes.size()));
    bytes.resize(std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
    return bytes;
}

}  // namespace

FileKind fileKindByName(const std::string& path) {
    if (endsWithAny(path, {".vdb"})) return FileKind::Vdb;
    if (endsWithAny(path, {".nii", ".nii.gz"})) return FileKind::Nifti;
    if (endsWithAny(path, {".mgh", ".mgz"})) return FileKind::Mgh;
    if (endsWithAny(path, {".mha", ".mhd"})) return FileKind::MetaImage;
    if (endsWithAny(path, {".png", ".tif", ".tiff", ".jpg", ".jpeg", ".bmp", ".exr"})) return FileKind::Image;
    return FileKind::Other;
}

FileKind fileKind(const std::string& path) {
    std::error_code error;
    if (std::filesystem::is_directory(path, error)) return FileKind::Folder;
    if (!std::filesystem::is_regular_file(path, error)) return FileKind::Other;
    const std::string bytes = leadingBytes(path);
    if (bytes.size() >= sizeof kAssetMagic && std::memcmp(bytes.data(), kAssetMagic, sizeof kAssetMagic) == 0) {
        return FileKind::Asset;
    }
    std::int32_t vdbMagic = 0;
    if (bytes.size() >= sizeof vdbMagic) std::memcpy(&vdbMagic, bytes.data(), sizeof vdbMagic);
    if (vdbMagic == openvdb::OPENVDB_MAGIC) return FileKind::Vdb;
    const FileKind byName = fileKindByName(path);
    return byName == FileKind::Vdb ? FileKind::Other : byName;
}

OutputFormat outputFormat(const std::string& path) {
    if (endsWithAny(path, {".vdb"})) return OutputFormat::Vdb;
    if (endsWithAny(path, {".nii", ".nii.gz"})) return OutputFormat::Nifti;
    if (endsWithAny(path, {".png"})) return OutputFormat::Png;
    if (endsWithAny(path, {".exr"})) return OutputFormat::Exr;
    return OutputFormat::Other;
}

}  // namespace gvr
