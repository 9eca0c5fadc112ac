// One libFuzzer target per input format, all built from this file: GVR_FUZZ_FORMAT
// names the format. Each input is written to a file, or to a file in a folder,
// and read the way `gvr ingest` (or, for assets, `gvr info`) reads a user's file;
// the JSON inputs as render (a transfer function, then its value levels), render
// --label-style and bench read theirs, and a results folder as bench --resume does.
// The contract under test: any bytes give a grid, an asset or an InputError.
// Any other exception, a crash, a leak or undefined behaviour is a finding.

#include "bench/BenchManifest.h"
#include "bench/BenchTable.h"
#include "io/Ingest.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "io/formats/LabelStyleFile.h"
#include "io/formats/TransferFunctionFile.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/SampleType.h"
#include "render/SliceStack.h"

#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

// A fuzzer process runs under libFuzzer's 2 GB RSS limit; the readers' memory
// check must refuse before that, as it would on a smaller machine.
constexpr std::uint64_t kMemoryCeiling = 512ull << 20;

struct Format {
    const char* file;  // the input's name inside the scratch folder
    bool asFolder;     // ingest the folder (DICOM series, image stack), not the file
};

Format format() {
    const std::string name = GVR_FUZZ_FORMAT;
    if (name == "nifti") return {"volume.nii", false};
    if (name == "metaimage") return {"volume.mha", false};
    if (name == "mgh") return {"volume.mgh", false};
    if (name == "raw") return {"volume.raw", false};
    if (name == "dicom") return {"series/slice.dcm", true};
    if (name == "image") return {"stack/slice.png", true};
    if (name == "vdb") return {"volume.vdb", false};
    if (name == "asset") return {"fit.gvr", false};
    if (name == "tf") return {"tf.json", false};
    if (name == "labelstyle") return {"style.json", false};
    if (name == "manifest") return {"manifest.json", false};
    if (name == "results") return {"results/results.csv", false};
    std::abort();
}

const fs::path& scratchFolder() {
    static const fs::path folder = [] {
        std::string pattern = (fs::temp_directory_path() / "gvr-fuzz-XXXXXX").string();
        if (!mkdtemp(pattern.data())) std::abort();
        return fs::path(pattern);
    }();
    return folder;
}

void writeFile(const fs::path& path, const std::uint8_t* data, std::size_t size) {
    fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// Raw data has no header: the first 16 bytes choose the layout that the flags
/// (--raw-dims, --raw-type, --endian, --header-bytes) would give.
gvr::ReadOptions rawOptions(const std::uint8_t* data, std::size_t size) {
    gvr::ReadOptions options;
    gvr::RawLayout layout;
    std::uint8_t bytes[16] = {};
    std::memcpy(bytes, data, std::min<std::size_t>(size, 16));
    for (int a = 0; a < 3; ++a) layout.dims[a] = 1 + (bytes[2 * a] | (bytes[2 * a + 1] << 8));
    const gvr::SampleType types[] = {gvr::SampleType::UInt8,   gvr::SampleType::Int8,   gvr::SampleType::UInt16,
                                     gvr::SampleType::Int16,   gvr::SampleType::UInt32, gvr::SampleType::Int32,
                                     gvr::SampleType::Float32, gvr::SampleType::Float64};
    layout.type = types[bytes[6] % 8];
    layout.channels = bytes[7] % 2 == 0 ? 1 : 3;
    layout.bigEndian = bytes[8] % 2 == 1;
    layout.headerBytes = bytes[9];
    options.raw = layout;
    return options;
}

void readAsUserInput(const fs::path& path, const Format& format, const std::uint8_t* data, std::size_t size) {
    const std::string input = format.asFolder ? path.parent_path().string() : path.string();
    const std::string name = GVR_FUZZ_FORMAT;
    if (name == "asset") {
        gvr::readAsset(input);
        return;
    }
    if (name == "tf") {
        // Extreme points once crashed the renderer's levels, not the reader.
        const gvr::ValueLevels levels(gvr::readTransferFunction(input), 1.0);
        for (float value : {-3e38f, -1.0f, 0.0f, 1e-30f, 1.0f, 3e38f}) levels.rgba(levels.levelOf(value));
        levels.anyVisible(-1.0f, 1.0f);
        return;
    }
    if (name == "labelstyle") {
        gvr::readLabelStyles(input);
        return;
    }
    if (name == "manifest") {
        gvr::benchUnits(gvr::readBenchManifest(input));
        return;
    }
    if (name == "results") {
        const gvr::ResultsTable table(path.parent_path().string(), (scratchFolder() / "manifest.json").string(),
                                      /*resume=*/true, /*retryFailed=*/size > 0 && data[0] % 2 == 1);
        return;
    }
    gvr::IngestOptions options;
    if (std::string(GVR_FUZZ_FORMAT) == "raw") options.read = rawOptions(data, size);
    gvr::ingest(input, options);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    gvr::initializeOpenVdb();
    gvr::setMemoryCeiling(kMemoryCeiling);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const Format chosen = format();
    const fs::path path = scratchFolder() / chosen.file;
    if (std::string(GVR_FUZZ_FORMAT) == "asset") {
        // Assets end in a CRC-32 of what precedes it. Appending it here lets the
        // fuzzer reach the decoder behind the checksum; the tests cover bad checksums.
        std::string bytes(reinterpret_cast<const char*>(data), size);
        const auto crc = std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(data), uInt(size)));
        bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
        writeFile(path, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    } else if (std::string(GVR_FUZZ_FORMAT) == "results" && size > 0 && data[0] % 4 != 0) {
        // Most inputs are rows under the header a bench writes, so that the fuzzer
        // reaches the rows' checks; the rest are whole files, headers included.
        const std::string bytes =
            gvr::resultsCsvHeader() + std::string(reinterpret_cast<const char*>(data) + 1, size - 1);
        writeFile(path, reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    } else {
        writeFile(path, data, size);
    }
    try {
        readAsUserInput(path, chosen, data, size);
    } catch (const gvr::InputError&) {
        // The promised answer to bad input.
    }
    return 0;
}
