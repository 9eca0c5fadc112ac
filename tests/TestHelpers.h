// Shared fixtures for the gvr tests: temporary folders, shared data paths and
// small synthetic volumes.
#pragma once

#include "io/DenseVolume.h"
#include "pipeline/GaussianAsset.h"
#include "pipeline/GaussianParameters.h"
#include "render/Framebuffer.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gvr::test {

/// The sum of an image's opacities: how much of it is covered, in pixels.
inline double opacitySum(const Framebuffer& image) {
    double sum = 0.0;
    for (std::size_t p = 3; p < image.rgba.size(); p += 4) sum += image.rgba[p];
    return sum;
}

/// A fresh folder under the system temporary folder, removed with its contents.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    std::string path(const std::string& name) const { return (mRoot / name).string(); }
    const std::filesystem::path& root() const { return mRoot; }

private:
    std::filesystem::path mRoot;
};

/// A TempDir that the children of death tests share. In gtest's "threadsafe" style
/// a child runs its test again from the start: with a TempDir of its own it would
/// write into another folder, and the parent would check one the child never touched.
class DeathTestDir {
public:
    DeathTestDir();
    ~DeathTestDir();
    DeathTestDir(const DeathTestDir&) = delete;
    DeathTestDir& operator=(const DeathTestDir&) = delete;

    std::string path(const std::string& name) const { return (mRoot / name).string(); }
    const std::filesystem::path& root() const { return mRoot; }

private:
    std::unique_ptr<TempDir> mOwned;  // in the parent only
    std::filesystem::path mRoot;
};

/// Absolute path of a file or folder under ../shared/data.
std::string sharedData(const std::string& relative);

std::string readBytes(const std::string& path);

/// The message of the @a Error that @a run throws, or "" when it throws none.
template <typename Error>
std::string errorMessageOf(const std::function<void()>& run) {
    try {
        run();
    } catch (const Error& error) {
        return error.what();
    }
    return "";
}
void writeBytes(const std::string& path, const std::string& bytes);
/// The bytes of @a values in the host's order, as a raw volume file holds them.
template <typename T>
std::string rawBytes(const std::vector<T>& values) {
    return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}
/// The low two or four bytes of @a value, least significant first, as file formats store them.
std::string littleEndian16(std::uint32_t value);
std::string littleEndian32(std::uint32_t value);
/// Copies @a from to @a to, keeping only the first @a keep bytes.
void copyTruncated(const std::string& from, const std::string& to, std::size_t keep);

/// A volume of @a dims filled from @a values (i fastest), stored as T.
template <typename T>
DenseVolume makeVolume(std::array<std::int64_t, 3> dims, const std::vector<T>& values, SampleType type,
                       int channels = 1) {
    DenseVolume volume;
    volume.dims = dims;
    volume.type = type;
    volume.channels = channels;
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    volume.samples.assign(bytes, bytes + values.size() * sizeof(T));
    return volume;
}

/// An ingested float grid of @a dims whose voxel (i, j, k) holds value(i, j, k),
/// with spacing @a spacingMm; voxels at or below @a threshold are inactive (unset:
/// those at the minimum, as ingest does).
openvdb::GridBase::Ptr makeGrid(std::array<int, 3> dims, const std::function<float(int, int, int)>& value,
                                openvdb::Vec3d spacingMm = openvdb::Vec3d(1.0),
                                std::optional<double> threshold = std::nullopt);

/// @a grid fitted by @a gaussians Gaussians in three iterations, with the residual
/// layer that takes them to within @a bound of its voxels (the inactive ones at
/// the background), as fit --max-error adds it.
GaussianAsset boundedAsset(const openvdb::GridBase::Ptr& grid, std::size_t gaussians, double bound);

/// A colour grid of @a dims whose voxel (i, j, k) holds colour(i, j, k), every voxel
/// active, on a background of @a outside, with spacing @a spacingMm.
openvdb::GridBase::Ptr makeColourGrid(std::array<int, 3> dims,
                                      const std::function<openvdb::Vec3s(int, int, int)>& colour,
                                      const openvdb::Vec3s& outside, openvdb::Vec3d spacingMm = openvdb::Vec3d(1.0));

/// A blob on a gentle ripple over a floor of 20: smooth content with one bright
/// centre, for fits that must converge quickly (the bricked-fit tests).
openvdb::GridBase::Ptr blobGrid(std::array<int, 3> dims);

struct CommandResult {
    int exitCode = -1;
    std::string out, err;
};

/// Runs the gvr executable with @a arguments (already shell-quoted where needed),
/// capturing its output through files in @a dir.
CommandResult runGvr(const std::string& arguments, const TempDir& dir);

std::size_t lineCount(const std::string& text);

/// A small ingested grid in @a dir: two soft blobs in a 24 x 20 x 16 uint8 raw
/// volume (all zero when @a empty). @return its path.
std::string smallGrid(const TempDir& dir, bool empty = false);

/// @a count Gaussians of assorted shapes (standard deviations about 1 to 4.5
/// voxels) with means spread over [0, extent)^3 in index space.
GaussianParameters randomGaussians(std::size_t count, int channels, float extent, unsigned seed);

}  // namespace gvr::test

/// Skips the test when the shared data sets are not beside the checkout.
#define GVR_REQUIRE_SHARED_DATA()                                     \
    if (!std::filesystem::exists(gvr::test::sharedData("README.md"))) \
    GTEST_SKIP() << "shared data not found at " << gvr::test::sharedData("")

// AddressSanitizer reserves terabytes of address space at start, so a test that
// lowers ulimit -v cannot run under it. GCC says so with __SANITIZE_ADDRESS__,
// clang with __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define GVR_UNDER_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GVR_UNDER_ADDRESS_SANITIZER 1
#endif
#endif
