#include "TestHelpers.h"

#include <fstream>
#include <random>
#include <sstream>

namespace gvr::test {

TempDir::TempDir() {
    std::random_device random;
    mRoot = std::filesystem::temp_directory_path() /
            ("gvr-test-" + std::to_string(random()) + std::to_string(random()));
    std::filesystem::create_directories(mRoot);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(mRoot, ignored);
}

std::string sharedData(const std::string& relative) {
    return (std::filesystem::path(GVR_SHARED_DATA) / relative).lexically_normal().string();
}

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

void copyTruncated(const std::string& from, const std::string& to, std::size_t keep) {
    writeBytes(to, readBytes(from).substr(0, keep));
}

}  // namespace gvr::test
