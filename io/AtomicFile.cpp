#include "AtomicFile.h"

#include "Error.h"

#include <unistd.h>

#include <filesystem>
#include <system_error>

namespace gvr {

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    if (!fs::is_directory(folder)) throw InputError(path, "output folder does not exist");
    // The temporary lives in the same folder so the final rename cannot cross devices,
    // and keeps the file's extension for writers that choose a format by it (nifticlib).
    const fs::path temporary =
        folder / (".tmp" + std::to_string(getpid()) + "-" + target.filename().string());
    try {
        write(temporary.string());
        fs::rename(temporary, target);
    } catch (...) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw;
    }
}

}  // namespace gvr
