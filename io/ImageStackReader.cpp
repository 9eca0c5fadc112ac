// Stacks of 2D images (PNG, TIFF, JPEG, ...) and multi-page TIFF, through OpenImageIO.
// Every page of every file becomes one slice, in the order given.

#include "Error.h"
#include "ImageFraming.h"
#include "Readers.h"

#include <OpenImageIO/imageio.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>

namespace gvr {

namespace {

struct Page {
    std::string file;
    int subimage = 0;
};

struct StackLayout {
    int width = 0, height = 0;
    int channels = 0;  // 1 grey or 3 RGB, after dropping alpha
    SampleType type = SampleType::UInt8;
    std::vector<Page> pages;
};

SampleType sampleTypeOf(const OIIO::TypeDesc& format) {
    if (format == OIIO::TypeDesc::UINT8) return SampleType::UInt8;
    if (format == OIIO::TypeDesc::UINT16) return SampleType::UInt16;
    return SampleType::Float32;  // half, float and wide integers all fit
}

OIIO::TypeDesc typeDescOf(SampleType type) {
    if (type == SampleType::UInt8) return OIIO::TypeDesc::UINT8;
    if (type == SampleType::UInt16) return OIIO::TypeDesc::UINT16;
    return OIIO::TypeDesc::FLOAT;
}

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& file) {
    auto input = OIIO::ImageInput::open(file);
    if (!input) {
        std::string why = OIIO::geterror();
        if (why.empty()) why = "not a readable image";
        throw InputError(file, "cannot read image: " + why);
    }
    return input;
}

void addPage(const std::string& file, int subimage, const OIIO::ImageSpec& spec,
             StackLayout& layout) {
    const int channels = spec.nchannels >= 3 ? 3 : 1;
    const SampleType type = sampleTypeOf(spec.format);
    if (layout.pages.empty()) {
        layout.width = spec.width;
        layout.height = spec.height;
        layout.channels = channels;
        layout.type = type;
    } else if (spec.width != layout.width || spec.height != layout.height) {
        throw InputError(file, "slice is " + std::to_string(spec.width) + "x" +
                                   std::to_string(spec.height) + " but earlier slices are " +
                                   std::to_string(layout.width) + "x" +
                                   std::to_string(layout.height));
    } else if (channels != layout.channels) {
        throw InputError(file, std::string("slice is ") + (channels == 3 ? "colour" : "grey") +
                                   " but earlier slices are " +
                                   (layout.channels == 3 ? "colour" : "grey"));
    } else if (type != layout.type) {
        throw InputError(file, "slice stores " + sampleTypeName(type) +
                                   " but earlier slices store " + sampleTypeName(layout.type));
    }
    if (spec.depth > 1) throw InputError(file, "volume images are not supported as slices");
    layout.pages.push_back({file, subimage});
}

/// No image codec expands its bytes more than about 1000:1 (deflate's limit; LZW
/// reaches about 2700:1), so a file whose header claims more pixels than this can
/// hold is corrupt or a decompression bomb, and is refused before the memory is spent.
constexpr double kMostDecodedBytesPerFileByte = 4096.0;

void checkFileCanHoldItsPages(const std::string& file, const OIIO::ImageSpec& spec, std::size_t pages) {
    // OpenImageIO reads a TIFF a strip at a time, into a buffer of the header's
    // RowsPerStrip rows, however few rows the image has.
    const double rows = std::max(double(spec.height), double(spec.get_int_attribute("tiff:RowsPerStrip", 0)));
    const double decoded = double(spec.width) * rows * double(std::max(spec.depth, 1)) *
                           double(spec.nchannels) * double(spec.format.size()) * double(pages);
    const double fileBytes = double(std::filesystem::file_size(file));
    if (decoded > fileBytes * kMostDecodedBytesPerFileByte) {
        const std::string strips =
            rows > spec.height ? " in strips of " + std::to_string(std::uint64_t(rows)) + " rows" : "";
        throw InputError(file, "corrupt image header: " + std::to_string(spec.width) + "x" +
                                   std::to_string(spec.height) + " pixels" + strips + " cannot come from a file of " +
                                   std::to_string(std::uint64_t(fileBytes)) + " bytes");
    }
}

StackLayout readLayout(const std::vector<std::string>& files) {
    StackLayout layout;
    for (const std::string& file : files) {
        checkImageFraming(file);
        auto input = openImage(file);
        OIIO::ImageSpec spec = input->spec();
        for (int subimage = 0;; ++subimage) {
            checkFileCanHoldItsPages(file, spec, std::size_t(subimage) + 1);
            addPage(file, subimage, spec, layout);
            if (!input->seek_subimage(subimage + 1, 0, spec)) break;
        }
    }
    return layout;
}

void readPage(const StackLayout& layout, std::size_t index, DenseVolume& volume) {
    const Page& page = layout.pages[index];
    auto input = openImage(page.file);
    const std::size_t pageBytes = std::size_t(layout.width) * layout.height * layout.channels *
                                  bytesPerSample(layout.type);
    unsigned char* destination = volume.samples.data() + index * pageBytes;
    if (!input->read_image(page.subimage, 0, 0, layout.channels, typeDescOf(layout.type),
                           destination)) {
        throw InputError(page.file, "truncated or corrupt image: " + input->geterror());
    }
}

}  // namespace

DenseVolume readImageStack(const std::vector<std::string>& files, const std::string& culprit,
                           const ReadOptions& options) {
    if (files.empty()) throw InputError(culprit, "no image files found");
    const StackLayout layout = readLayout(files);

    DenseVolume volume;
    volume.dims = {layout.width, layout.height, std::int64_t(layout.pages.size())};
    volume.channels = layout.channels;
    volume.type = layout.type;
    setGivenSpacing(options, volume);
    allocateSamples(volume, culprit);

    ProgressCounter progress(options.progress, layout.pages.size());
    tbb::parallel_for(std::size_t(0), layout.pages.size(), [&](std::size_t index) {
        readPage(layout, index, volume);
        progress.advance();
    });
    return volume;
}

}  // namespace gvr
