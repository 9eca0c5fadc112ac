#include "io/formats/ImageFile.h"

#include "io/formats/FileKind.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "pipeline/LowerCase.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace gvr {

namespace {

std::string lowerExtension(const std::string& path) {
    return lowerCase(std::filesystem::path(path).extension().string());
}

std::vector<std::uint8_t> straightBytes(int width, int height, const float* rgba) {
    std::vector<std::uint8_t> bytes(std::size_t(width) * height * 4);
    for (std::size_t p = 0; p < std::size_t(width) * height; ++p) {
        const float alpha = rgba[p * 4 + 3];
        for (int c = 0; c < 4; ++c) {
            const float v = c == 3 ? alpha : (alpha > 0.0f ? rgba[p * 4 + c] / alpha : 0.0f);
            bytes[p * 4 + c] = std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
    }
    return bytes;
}

}  // namespace

void writeImage(const std::string& path, int width, int height, const float* premultipliedRgba) {
    const OutputFormat format = outputFormat(path);
    if (format != OutputFormat::Png && format != OutputFormat::Exr) {
        throw InputError(path,
                         "unknown image format '" + lowerExtension(path) + "'; write .png (8-bit) or .exr (float)");
    }
    // Encoded in memory, then written here: OpenImageIO's PNG writer does not see a
    // short write (a full disk, ulimit -f) and would leave a cut file behind.
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    auto out = OIIO::ImageOutput::create(path, &memory);
    if (!out) throw InputError(path, "OpenImageIO cannot write this format: " + OIIO::geterror());
    const bool png = format == OutputFormat::Png;
    OIIO::ImageSpec spec(width, height, 4, png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    spec.attribute("oiio:UnassociatedAlpha", png ? 1 : 0);
    const std::vector<std::uint8_t> bytes =
        png ? straightBytes(width, height, premultipliedRgba) : std::vector<std::uint8_t>();
    const bool written = out->open(path, spec) &&
                         (png ? out->write_image(OIIO::TypeDesc::UINT8, bytes.data())
                              : out->write_image(OIIO::TypeDesc::FLOAT, premultipliedRgba)) &&
                         out->close();
    if (!written) throw InputError(path, "encoding the image failed: " + out->geterror());
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream file(temporary, std::ios::binary);
        file.write(reinterpret_cast<const char*>(encoded.data()), std::streamsize(encoded.size()));
        file.close();
        if (!file) throw InputError(path, "cannot write the image (disk full?)");
    });
}

}  // namespace gvr
