#include "ComparisonInput.h"

#include "Error.h"
#include "Readers.h"
#include "VolumeMetadata.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
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
    FloatVolume image(openvdb::Coord(spec.width, spec.height, 1), spec.nchannels);
    if (!input.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values.data())) {
        throw InputError(path, "cannot decode the image: " + input.geterror());
    }
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
    const IngestResult loaded = loadOrIngest(path, options);
    input.volume = sampleGrid(*loaded.grid, volumeBox(*loaded.grid));
    const auto metadata = readVolumeMetadata(*loaded.grid);
    input.dataRange = metadata ? metadata->valueMax - metadata->valueMin : sampleRange(input.volume);
    return input;
}

}  // namespace gvr
