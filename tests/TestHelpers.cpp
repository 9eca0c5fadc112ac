#include "tests/TestHelpers.h"

#include "io/GridBuilder.h"
#include "io/asset/AssetFile.h"
#include "workflow/FitJob.h"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

namespace gvr::test {

TempDir::TempDir() {
    std::random_device random;
    mRoot =
        std::filesystem::temp_directory_path() / ("gvr-test-" + std::to_string(random()) + std::to_string(random()));
    std::filesystem::create_directories(mRoot);
}

TempDir::~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(mRoot, ignored);
}

namespace {
constexpr const char* kDeathTestDirVariable = "GVR_DEATH_TEST_DIR";
}

DeathTestDir::DeathTestDir() {
    if (const char* parents = std::getenv(kDeathTestDirVariable)) {
        mRoot = parents;
        return;
    }
    mOwned = std::make_unique<TempDir>();
    mRoot = mOwned->root();
    setenv(kDeathTestDirVariable, mRoot.c_str(), 1);
}

DeathTestDir::~DeathTestDir() {
    if (mOwned) unsetenv(kDeathTestDirVariable);
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

std::string littleEndian16(std::uint32_t value) { return {char(value & 0xff), char((value >> 8) & 0xff)}; }

std::string littleEndian32(std::uint32_t value) { return littleEndian16(value & 0xffff) + littleEndian16(value >> 16); }

void copyTruncated(const std::string& from, const std::string& to, std::size_t keep) {
    writeBytes(to, readBytes(from).substr(0, keep));
}

openvdb::GridBase::Ptr makeGrid(std::array<int, 3> dims, const std::function<float(int, int, int)>& value,
                                openvdb::Vec3d spacingMm, std::optional<double> threshold) {
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
    settings.threshold = threshold;
    return buildGrid(volume, settings);
}

openvdb::GridBase::Ptr makeColourGrid(std::array<int, 3> dims,
                                      const std::function<openvdb::Vec3s(int, int, int)>& colour,
                                      const openvdb::Vec3s& outside, openvdb::Vec3d spacingMm) {
    const openvdb::Vec3SGrid::Ptr grid = openvdb::Vec3SGrid::create(outside);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
    grid->transform().preScale(spacingMm);
    openvdb::Vec3SGrid::Accessor accessor = grid->getAccessor();
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) accessor.setValue(openvdb::Coord(i, j, k), colour(i, j, k));
        }
    }
    return grid;
}

openvdb::GridBase::Ptr blobGrid(std::array<int, 3> dims) {
    return makeGrid(dims, [dims](int i, int j, int k) {
        const double x = i - 0.5 * dims[0], y = j - 0.5 * dims[1], z = k - 0.5 * dims[2];
        return float(20.0 + 200.0 * std::exp(-(x * x + y * y + z * z) / 90.0) + 30.0 * std::sin(0.4 * i));
    });
}

CommandResult runGvr(const std::string& arguments, const TempDir& dir) {
    const std::string outPath = dir.path("stdout.txt"), errPath = dir.path("stderr.txt");
    const std::string command =
        std::string("'") + GVR_EXECUTABLE + "' " + arguments + " >'" + outPath + "' 2>'" + errPath + "' </dev/null";
    const int status = std::system(command.c_str());
    CommandResult run;
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.out = readBytes(outPath);
    run.err = readBytes(errPath);
    std::filesystem::remove(outPath);
    std::filesystem::remove(errPath);
    return run;
}

std::size_t lineCount(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

std::string smallGrid(const TempDir& dir, bool empty) {
    std::string bytes;
    for (int k = 0; k < 16; ++k) {
        for (int j = 0; j < 20; ++j) {
            for (int i = 0; i < 24; ++i) {
                const double d2 = (i - 8) * (i - 8) + (j - 10) * (j - 10) + (k - 8) * (k - 8);
                bytes.push_back(empty ? 0 : char(std::lround(200.0 * std::exp(-d2 / 20.0))));
            }
        }
    }
    writeBytes(dir.path("small.raw"), bytes);
    const std::string grid = dir.path(empty ? "empty.vdb" : "small.vdb");
    const CommandResult run = runGvr("ingest -q '" + dir.path("small.raw") + "' -o '" + grid +
                                         "' --raw-dims 24,20,16 --raw-type uint8 --spacing 1,1,1",
                                     dir);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    return grid;
}

GaussianAsset boundedAsset(const openvdb::GridBase::Ptr& grid, std::size_t gaussians, double bound) {
    FitInput input;
    input.inMemory.grid = grid;
    FitRequest request;
    request.options.gaussians = gaussians;
    request.options.settings.seconds = 0.0;
    request.options.settings.iterations = 3;
    request.bound = BoundRequest::exactly(bound);
    const FitJob job(input, request);
    return decodeAsset(job.run().result.file, job.name());
}

GaussianParameters randomGaussians(std::size_t count, int channels, float extent, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), place(0.0f, extent);
    GaussianParameters params(count, channels);
    for (std::size_t g = 0; g < count; ++g) {
        for (int a = 0; a < 3; ++a) params.at(kMeans, g)[a] = place(random);
        for (int k = 0; k < 4; ++k) params.at(kRotations, g)[k] = unit(random);
        for (int a = 0; a < 3; ++a) params.at(kLogScales, g)[a] = 0.8f + 0.7f * unit(random);
        *params.at(kOpacityLogits, g) = unit(random);
        for (int c = 0; c < channels; ++c) params.at(kColours, g)[c] = 0.5f + 0.5f * unit(random);
    }
    return params;
}

}  // namespace gvr::test
