#include "TestHelpers.h"

#include "GridBuilder.h"

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

openvdb::GridBase::Ptr makeGrid(std::array<int, 3> dims, const std::function<float(int, int, int)>& value,
                                openvdb::Vec3d spacingMm) {
    std::vector<float> values;
    values.reserve(std::size_t(dims[0]) * dims[1] * dims[2]);
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) values.push_back(value(i, j, k));
        }
    }
    DenseVolume volume = makeVolume<float>({dims[0], dims[1], dims[2]}, values, SampleType::Float32);
    volume.worldFromIndex = worldFromSpacing(spacingMm);
    GridBuildSettings settings;
    settings.sourceFile = "synthetic";
    return buildGrid(volume, settings);
}

}  // namespace gvr::test
