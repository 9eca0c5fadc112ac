#include "io/guard/InputFile.h"

#include "pipeline/Error.h"

#include <filesystem>

namespace gvr {

void requireNoNulByte(const std::string& path) {
    const std::size_t nul = path.find('\0');
    if (nul == std::string::npos) return;
    throw InputError(path.substr(0, nul) + "\\0" + path.substr(nul + 1),
                     "a path with a NUL byte in it names another file than it says");
}

void requireRegularFile(const std::string& path) {
    namespace fs = std::filesystem;
    requireNoNulByte(path);
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status)) throw InputError(path, "no such file");
    if (fs::is_directory(status)) throw InputError(path, "is a folder, not a file");
    if (!fs::is_regular_file(status)) {
        throw InputError(path, "is not a regular file (a FIFO, socket or device); gvr reads files only");
    }
}

}  // namespace gvr
