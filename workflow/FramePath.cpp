#include "workflow/FramePath.h"

#include <filesystem>
#include <iomanip>
#include <sstream>

namespace gvr {

std::string framePath(const std::string& output, int index, int count) {
    if (count <= 1) return output;
    const std::filesystem::path path(output);
    std::ostringstream name;
    name << path.stem().string() << "_" << std::setw(4) << std::setfill('0') << index << path.extension().string();
    return (path.parent_path() / name.str()).string();
}

}  // namespace gvr
