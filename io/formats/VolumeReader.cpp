// Chooses a reader from what INPUT is: a glob pattern, or what fileKind() makes of it.

#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/formats/Readers.h"
#include "io/guard/InputFile.h"
#include "pipeline/Error.h"

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace gvr {

namespace {

namespace fs = std::filesystem;

/// "10.png" after "2.png": digit runs compare as numbers, everything else as text.
bool naturalLess(const std::string& a, const std::string& b) {
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (std::isdigit((unsigned char)a[i]) && std::isdigit((unsigned char)b[j])) {
            std::size_t iEnd = i, jEnd = j;
            while (iEnd < a.size() && std::isdigit((unsigned char)a[iEnd])) ++iEnd;
            while (jEnd < b.size() && std::isdigit((unsigned char)b[jEnd])) ++jEnd;
            std::string x = a.substr(i, iEnd - i), y = b.substr(j, jEnd - j);
            x.erase(0, std::min(x.find_first_not_of('0'), x.size()));
            y.erase(0, std::min(y.find_first_not_of('0'), y.size()));
            if (x.size() != y.size()) return x.size() < y.size();
            if (x != y) return x < y;
            i = iEnd;
            j = jEnd;
        } else {
            if (a[i] != b[j]) return a[i] < b[j];
            ++i;
            ++j;
        }
    }
    return a.size() - i < b.size() - j;
}

std::vector<std::string> naturallySorted(std::vector<std::string> files) {
    std::sort(files.begin(), files.end(), naturalLess);
    return files;
}

std::vector<std::string> imagesInFolder(const std::string& folder) {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (entry.is_regular_file() && fileKindByName(entry.path().string()) == FileKind::Image) {
            files.push_back(entry.path().string());
        }
    }
    return naturallySorted(files);
}

/// A pattern that names no file itself: a file called "a[1].png" is just a file.
bool isGlobPattern(const std::string& input) {
    return input.find_first_of("*?[") != std::string::npos && !fs::exists(input);
}

std::vector<std::string> globFiles(const std::string& pattern) {
    glob_t matches{};
    std::vector<std::string> files;
    if (glob(pattern.c_str(), 0, nullptr, &matches) == 0) {
        files.assign(matches.gl_pathv, matches.gl_pathv + matches.gl_pathc);
    }
    globfree(&matches);
    return naturallySorted(files);
}

bool folderHasDicom(const std::string& folder) {
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (entry.is_regular_file() && isDicomFile(entry.path().string())) return true;
    }
    return false;
}

std::unique_ptr<SliceSource> openFolder(const std::string& folder, const ReadOptions& options) {
    if (fs::is_empty(folder)) throw InputError(folder, "folder is empty");
    if (folderHasDicom(folder)) return openDicomSeries(folder, options);
    const std::vector<std::string> images = imagesInFolder(folder);
    if (images.empty()) {
        throw InputError(folder,
                         "folder holds neither DICOM files nor images "
                         "(.png, .tif, .tiff, .jpg, .jpeg, .bmp, .exr)");
    }
    return openImageStack(images, folder, options);
}

/// The formats that are read whole, all of which carry their own geometry.
DenseVolume readFileByFormat(const std::string& path, const ReadOptions& options) {
    switch (fileKind(path)) {
        case FileKind::Vdb:
            return readVdb(path, options);
        case FileKind::Nifti:
            return readNifti(path, options);
        case FileKind::Mgh:
            return readMgh(path, options);
        case FileKind::MetaImage:
            return readMetaImage(path, options);
        default:
            break;
    }
    if (fileKindByName(path) == FileKind::Vdb) throw InputError(path, "not a VDB file (no OpenVDB magic number)");
    throw InputError(path,
                     "unknown volume format; gvr reads .nii/.nii.gz, .mgh/.mgz, .mha/.mhd, "
                     ".vdb, a DICOM folder, image stacks, or raw data with `raw_dims`");
}

}  // namespace

void setGivenSpacing(const ReadOptions& options, DenseVolume& volume) {
    if (!options.spacingMm) {
        volume.warnings.push_back(
            "voxel spacing is unknown for this format; assuming 1 x 1 x 1 mm "
            "(set it with `spacing=X,Y,Z`)");
    }
    volume.worldFromIndex = worldFromSpacing(options.spacingMm.value_or(openvdb::Vec3d(1.0)));
}

std::unique_ptr<SliceSource> openSliceSource(const std::string& input, const ReadOptions& options) {
    if (isGlobPattern(input)) {
        const std::vector<std::string> files = globFiles(input);
        if (files.empty()) throw InputError(input, "pattern matches no files");
        for (const std::string& file : files) requireRegularFile(file);
        return openImageStack(files, input, options);
    }
    if (!fs::exists(input)) throw InputError(input, "no such file or folder");
    if (!fs::is_directory(input)) requireRegularFile(input);
    if (options.raw) return openRawSource(input, options);
    if (fs::is_directory(input)) return openFolder(input, options);
    if (fileKind(input) == FileKind::Image) return openImageStack({input}, input, options);
    return nullptr;
}

std::vector<std::string> filesReadFrom(const std::string& input) {
    if (isGlobPattern(input)) return globFiles(input);
    std::error_code error;
    if (fs::is_directory(input, error)) {
        std::vector<std::string> files;
        for (const auto& entry : fs::directory_iterator(input, error)) {
            const std::string file = entry.path().string();
            if (entry.is_regular_file() && (fileKindByName(file) == FileKind::Image || isDicomFile(file))) {
                files.push_back(file);
            }
        }
        return files;
    }
    if (fileKind(input) == FileKind::MetaImage) {
        try {
            return {input, metaImageDataFile(input)};
        } catch (const InputError&) {
            // Reading will refuse the header before anything is written.
        }
    }
    return {input};
}

namespace {

/// The formats read whole carry their own voxel size, so --spacing (for formats
/// without one) would be a silent choice between two answers: it is named.
DenseVolume readFile(const std::string& path, const ReadOptions& options) {
    DenseVolume volume = readFileByFormat(path, options);
    if (options.spacingMm) volume.warnings.push_back("`spacing` is ignored: the file gives its own voxel size");
    return volume;
}

}  // namespace

DenseVolume readVolume(const std::string& input, const ReadOptions& options) {
    if (const auto source = openSliceSource(input, options)) return readWholeVolume(*source, options.progress);
    return readFile(input, options);
}

}  // namespace gvr
