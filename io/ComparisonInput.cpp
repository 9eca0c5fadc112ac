#include "io/ComparisonInput.h"

#include "io/AssetExport.h"
#include "io/AssetFile.h"
#include "io/DenseCopy.h"

#include "io/Readers.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace gvr {

namespace {

/// An image file with one page; a multi-page TIFF is a volume.
std::unique_ptr<OIIO::ImageInput> openSingleImage(const std::string& path) {
    if (!std::filesystem::is_regular_file(path) || !isImageFile(path)) return nullptr;
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw InputError(path, "cannot read the image: " + OIIO::geterror());
    if (input->seek_subimage(1, 0)) return nullptr;
    input->seek_subimage(0, 0);
    return input;
}

FloatVolume readImage(OIIO::ImageInput& input, const std::string& path) {
    const OIIO::ImageSpec& spec = input.spec();
    if (spec.depth > 1) throw InputError(path, "is a volume image; gvr eval compares 2D images or volumes");
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 ||
        std::uint64_t(spec.width) * spec.height * spec.nchannels > (std::uint64_t(1) << 30)) {
        throw InputError(path, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" +
                                   std::to_string(spec.nchannels) + " samples is empty or too large to compare");
    }
    FloatVolume image(openvdb::Coord(spec.width, spec.height, 1), spec.nchannels);
    if (!input.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values.data())) {
        throw InputError(path, "cannot decode the image: " + input.geterror());
    }
    const auto nonFinite = std::count_if(image.values.begin(), image.values.end(), [](float v) { return !std::isfinite(v); });
    if (nonFinite > 0) throw InputError(path, std::to_string(nonFinite) + " samples are NaN or Inf");
    return image;
}

double sampleRange(const FloatVolume& volume) {
    if (volume.values.empty()) return 0.0;
    const auto [lo, hi] = std::minmax_element(volume.values.begin(), volume.values.end());
    return double(*hi) - double(*lo);
}

}  // namespace

ComparisonInput loadComparisonInput(const std::string& path, const IngestOptions& options) {
    ComparisonInput input;
    if (auto image = openSingleImage(path)) {
        input.volume = readImage(*image, path);
        input.isImage = true;
        input.dataRange = sampleRange(input.volume);
        return input;
    }
    // A Gaussian asset is compared as what it exports onto its source grid.
    const openvdb::GridBase::Ptr grid = isAssetFile(path) ? exportAsset(readAsset(path), ExportSettings{}).grids.front()
                                                          : loadOrIngest(path, options).grid;
    return comparisonInputOf(grid, path);
}

ComparisonInput comparisonInputOf(openvdb::GridBase::ConstPtr grid, const std::string& name) {
    ComparisonInput input;
    input.volume = denseCopy(*grid, volumeBox(*grid), name, "compare");
    const auto metadata = readVolumeMetadata(*grid);
    input.dataRange = metadata ? metadata->valueMax - metadata->valueMin : sampleRange(input.volume);
    input.grid = std::move(grid);
    return input;
}

}  // namespace gvr
