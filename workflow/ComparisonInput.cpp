#include "workflow/ComparisonInput.h"

#include "io/DenseCopy.h"
#include "io/GridBuilder.h"
#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/formats/Readers.h"
#include "pipeline/Error.h"
#include "pipeline/Luminance.h"
#include "pipeline/VolumeMetadata.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace gvr {

namespace {

/// An image file with one page; a multi-page TIFF is a volume.
std::unique_ptr<OIIO::ImageInput> openSingleImage(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw InputError(path, "cannot read the image: " + OIIO::geterror());
    if (input->seek_subimage(1, 0)) return nullptr;
    input->seek_subimage(0, 0);
    return input;
}

FloatVolume readImage(OIIO::ImageInput& input, const std::string& path) {
    const OIIO::ImageSpec& spec = input.spec();
    if (spec.depth > 1)
        throw InputError(path, "is a volume image; 2D images are compared with 2D images, volumes with volumes");
    if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1 ||
        std::uint64_t(spec.width) * spec.height * spec.nchannels > (std::uint64_t(1) << 30)) {
        throw InputError(path, "image of " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" +
                                   std::to_string(spec.nchannels) + " samples is empty or too large to compare");
    }
    FloatVolume image(openvdb::Coord(spec.width, spec.height, 1), spec.nchannels);
    if (!input.read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.values.data())) {
        throw InputError(path, "cannot decode the image: " + input.geterror());
    }
    const auto nonFinite =
        std::count_if(image.values.begin(), image.values.end(), [](float v) { return !std::isfinite(v); });
    if (nonFinite > 0) throw InputError(path, std::to_string(nonFinite) + " samples are NaN or Inf");
    return image;
}

double sampleRange(const FloatVolume& volume) {
    if (volume.values.empty()) return 0.0;
    const auto [lo, hi] = std::minmax_element(volume.values.begin(), volume.values.end());
    return double(*hi) - double(*lo);
}

std::string formatNumber(double value) {
    std::ostringstream text;
    text << value;
    return text.str();
}

/// The voxels at the format's padding value left out, the foreground set to what
/// ingest would keep, and the data range taken over the voxels kept.
void setApartPaddingAndBackground(ComparisonInput& input, const VolumeMetadata& metadata) {
    const FloatVolume& volume = input.volume;
    const std::size_t voxels = volume.voxelCount();
    const double cut = metadata.modality == "CT" && volume.channels == 1 ? kCtDefaultThreshold : metadata.valueMin;
    input.volume.foreground.assign(voxels, 0);
    if (metadata.markedPadding) input.excluded.assign(voxels, 0);
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t n = 0; n < voxels; ++n) {
        const double key = sampleKey(volume.values.data() + n * std::size_t(volume.channels), volume.channels);
        if (metadata.markedPadding && key == *metadata.markedPadding) {
            input.excluded[n] = 1;
            ++input.excludedVoxels;
            continue;
        }
        input.volume.foreground[n] = key > cut;
        lo = std::min(lo, key);
        hi = std::max(hi, key);
    }
    input.dataRange = lo <= hi ? hi - lo : 0.0;
    input.foregroundRule = "the voxels ingest keeps (above " + formatNumber(cut) + ")";
}

/// A source as read: every voxel, but those its format marks as no data.
ComparisonInput sourceAsRead(const std::string& path, IngestOptions options) {
    options.build.keepEveryVoxel = true;
    ComparisonInput input = comparisonInputOf(ingest(path, options).grid, path);
    const VolumeMetadata metadata = *readVolumeMetadata(*input.grid);
    setApartPaddingAndBackground(input, metadata);
    input.readAs = "the source as read, every voxel";
    if (metadata.markedPadding) {
        input.readAs += "; " + std::to_string(input.excludedVoxels) + " voxels at " +
                        formatNumber(*metadata.markedPadding) + ", which the file marks as padding (no data), left out";
    }
    return input;
}

}  // namespace

ComparisonInput loadComparisonInput(const std::string& path, const IngestOptions& options) {
    ComparisonInput input;
    const FileKind kind = fileKind(path);
    if (auto image = kind == FileKind::Image ? openSingleImage(path) : nullptr) {
        input.volume = readImage(*image, path);
        input.isImage = true;
        input.dataRange = sampleRange(input.volume);
        input.readAs = "a 2D image";
        return input;
    }
    if (kind == FileKind::Asset) {  // compared as what it exports onto its source grid
        input = comparisonInputOf(exportAsset(readAsset(path), ExportSettings{}).grids.front(), path);
        input.readAs = "the asset exported onto its source's voxels";
        return input;
    }
    if (kind == FileKind::Vdb) {
        input = comparisonInputOf(loadGridFile(path, options).grid, path);
        const auto metadata = readVolumeMetadata(*input.grid);
        input.readAs = metadata && metadata->threshold
                           ? "the grid as stored: voxels at or below its threshold " +
                                 formatNumber(*metadata->threshold) + " hold its background " +
                                 formatNumber(metadata->background)
                           : "the grid as stored";
        return input;
    }
    return sourceAsRead(path, options);
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
