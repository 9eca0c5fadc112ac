// Asset layout benchmark: the same Gaussians stored as the gvr asset given (its own
// version) and as an OpenVDB PointDataGrid with comparable codecs (16-bit fixed-point
// positions, half-float attributes, Blosc), at several PointDataGrid voxel sizes.
// Prints bytes per Gaussian for each, so the choice of layout rests on numbers.
//
//   bench_asset_layout ASSET

#include "io/asset/AssetFile.h"
#include "pipeline/GaussianKernel.h"

#include <openvdb/points/PointConversion.h>

#include <cstdio>
#include <filesystem>

namespace {

using namespace openvdb;

template <typename T>
void addAttribute(points::PointDataGrid& grid, const tools::PointIndexGrid& index, const std::string& name,
                  const std::vector<T>& values, Index stride) {
    points::appendAttribute<T, points::TruncateCodec>(grid.tree(), name, T(0), stride);
    points::populateAttribute(grid.tree(), index.tree(), name, points::PointAttributeVector<T>(values, stride), stride);
}

std::uint64_t pointDataGridBytes(const gvr::GaussianParameters& params, double voxelSize, const std::string& path) {
    const std::size_t n = params.count();
    std::vector<Vec3f> positions(n);
    std::vector<float> rotations(4 * n), opacities(n), colours(params.channels * n);
    std::vector<Vec3f> logScales(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* m = params.at(gvr::kMeans, i);
        positions[i] = Vec3f(m[0], m[1], m[2]);
        std::copy_n(params.at(gvr::kRotations, i), 4, &rotations[4 * i]);
        const float* s = params.at(gvr::kLogScales, i);
        logScales[i] = Vec3f(s[0], s[1], s[2]);
        opacities[i] = gvr::sigmoid(*params.at(gvr::kOpacityLogits, i));
        std::copy_n(params.at(gvr::kColours, i), params.channels, &colours[params.channels * i]);
    }
    const math::Transform::Ptr transform = math::Transform::createLinearTransform(voxelSize);
    const points::PointAttributeVector<Vec3f> positionWrapper(positions);
    const auto index = tools::createPointIndexGrid<tools::PointIndexGrid>(positionWrapper, *transform);
    auto grid = points::createPointDataGrid<points::FixedPointCodec<false>, points::PointDataGrid>(
        *index, positionWrapper, *transform);
    addAttribute(*grid, *index, "rotation", rotations, 4);
    addAttribute(*grid, *index, "log_scale", logScales, 1);
    addAttribute(*grid, *index, "opacity", opacities, 1);
    addAttribute(*grid, *index, "colour", colours, Index(params.channels));
    io::File file(path);
    file.setCompression(io::COMPRESS_BLOSC);
    file.write({grid});
    file.close();
    return std::filesystem::file_size(path);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: bench_asset_layout ASSET\n");
        return 2;
    }
    try {
        openvdb::initialize();
        const gvr::GaussianAsset asset = gvr::readAsset(argv[1]);
        const double n = double(asset.params.count());
        const std::uint64_t own = std::filesystem::file_size(argv[1]);
        std::printf("%zu Gaussians, %d channel(s)\n", asset.params.count(), asset.params.channels);
        std::printf("  gvr asset, format version %u: %llu bytes, %.2f B/Gaussian\n", asset.formatVersion,
                    (unsigned long long)own, own / n);
        const std::string scratch = (std::filesystem::temp_directory_path() / "gvr_layout_bench.vdb").string();
        for (double voxelSize : {1.0, 2.0, 4.0, 8.0}) {
            const std::uint64_t bytes = pointDataGridBytes(asset.params, voxelSize, scratch);
            std::printf(
                "  PointDataGrid, voxel %.0f (16-bit fixed positions, half attributes, Blosc): "
                "%llu bytes, %.2f B/Gaussian, %.2fx the gvr asset\n",
                voxelSize, (unsigned long long)bytes, bytes / n, double(bytes) / own);
        }
        std::filesystem::remove(scratch);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "bench_asset_layout: %s\n", error.what());
        return 1;
    }
    return 0;
}
