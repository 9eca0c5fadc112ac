// Stacks of 2D images (PNG, TIFF, JPEG, ...) and multi-page TIFF, through OpenImageIO.
// Every page of every file becomes one slice, in the order given.

#include "io/formats/Readers.h"
#include "io/formats/SliceSource.h"
#include "io/guard/ImageFraming.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"

#include <OpenImageIO/imageio.h>

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
    int channels = 0;    // 1 grey or 3 RGB, after dropping alpha
    bool alpha = false;  // some slice had an alpha channel
    SampleType type = SampleType::UInt8;
    std::vector<Page> pages;
};

/// Integers are read as the integers they are: asked for float, OpenImageIO would
/// scale an int16 TIFF's -1024..2036 HU to -0.031..0.062.
constexpr std::pair<OIIO::TypeDesc::BASETYPE, SampleType> kIntegerTypes[] = {
    {OIIO::TypeDesc::UINT8, SampleType::UInt8},   {OIIO::TypeDesc::INT8, SampleType::Int8},
    {OIIO::TypeDesc::UINT16, SampleType::UInt16}, {OIIO::TypeDesc::INT16, SampleType::Int16},
    {OIIO::TypeDesc::UINT32, SampleType::UInt32}, {OIIO::TypeDesc::INT32, SampleType::Int32},
};

SampleType sampleTypeOf(const OIIO::TypeDesc& format) {
    for (const auto& [base, type] : kIntegerTypes) {
        if (format.basetype == base) return type;
    }
    return SampleType::Float32;  // half, float, double and 64-bit integers
}

OIIO::TypeDesc typeDescOf(SampleType type) {
    for (const auto& [base, sample] : kIntegerTypes) {
        if (sample == type) return OIIO::TypeDesc(base);
    }
    return OIIO::TypeDesc::FLOAT;
}

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& file) {
    // Alpha is not part of the values: unassociated, colour and grey come as stored
    // (premultiplied, alpha 0 would zero them), and the alpha channel is not read.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto input = OIIO::ImageInput::open(file, &config);
    if (!input) {
        std::string why = OIIO::geterror();
        if (why.empty()) why = "not a readable image";
        throw InputError(file, "cannot read image: " + why);
    }
    return input;
}

void addPage(const std::string& file, int subimage, const OIIO::ImageSpec& spec, StackLayout& layout) {
    const int channels = spec.nchannels >= 3 ? 3 : 1;
    const SampleType type = sampleTypeOf(spec.format);
    if (layout.pages.empty()) {
        layout.width = spec.width;
        layout.height = spec.height;
        layout.channels = channels;
        layout.type = type;
    } else if (spec.width != layout.width || spec.height != layout.height) {
        throw InputError(file, "slice is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                                   " but earlier slices are " + std::to_string(layout.width) + "x" +
                                   std::to_string(layout.height));
    } else if (channels != layout.channels) {
        throw InputError(file, std::string("slice is ") + (channels == 3 ? "colour" : "grey") +
                                   " but earlier slices are " + (layout.channels == 3 ? "colour" : "grey"));
    } else if (type != layout.type) {
        throw InputError(
            file, "slice stores " + sampleTypeName(type) + " but earlier slices store " + sampleTypeName(layout.type));
    }
    if (spec.depth > 1) throw InputError(file, "volume images are not supported as slices");
    layout.alpha = layout.alpha || spec.alpha_channel >= 0 || spec.nchannels == 2 || spec.nchannels == 4;
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
    const double decoded = double(spec.width) * rows * double(std::max(spec.depth, 1)) * double(spec.nchannels) *
                           double(spec.format.size()) * double(pages);
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

class ImageStack : public SliceSource {
public:
    ImageStack(DenseVolume layout, const std::string& culprit, StackLayout stack)
        : SliceSource(std::move(layout), culprit), mStack(std::move(stack)) {}

private:
    void readSlices(std::int64_t first, std::int64_t count, unsigned char* destination,
                    const ProgressFn& progress) const override {
        decodeEachSlice(first, count, destination, progress,
                        [this](std::int64_t index, unsigned char* slice) { readPage(mStack.pages[index], slice); });
    }

    void readPage(const Page& page, unsigned char* destination) const {
        auto input = openImage(page.file);
        if (!input->read_image(page.subimage, 0, 0, mStack.channels, typeDescOf(mStack.type), destination)) {
            throw InputError(page.file, "truncated or corrupt image: " + input->geterror());
        }
    }

    StackLayout mStack;
};

}  // namespace

std::unique_ptr<SliceSource> openImageStack(const std::vector<std::string>& files, const std::string& culprit,
                                            const ReadOptions& options) {
    if (files.empty()) throw InputError(culprit, "no image files found");
    StackLayout stack = readLayout(files);

    DenseVolume layout;
    layout.dims = {stack.width, stack.height, std::int64_t(stack.pages.size())};
    layout.channels = stack.channels;
    layout.type = stack.type;
    if (stack.alpha) layout.warnings.push_back("the slices' alpha channel is ignored: values are read as stored");
    checkDimensions(culprit, layout.dims);
    setGivenSpacing(options, layout);
    return std::make_unique<ImageStack>(std::move(layout), culprit, std::move(stack));
}

}  // namespace gvr
