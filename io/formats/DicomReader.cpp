// A DICOM series (one folder) through GDCM, compressed transfer syntaxes included.
//
// Headers are read first (without pixel data) to sort the slices along the slice
// normal and to check that the series is consistent; only then are slices
// decoded, a slab at a time, in parallel.

#include "io/formats/Readers.h"
#include "io/formats/SliceSource.h"
#include "io/guard/ByteOrder.h"
#include "io/guard/DicomStructure.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"

#include <gdcmImageHelper.h>
#include <gdcmImageReader.h>
#include <gdcmReader.h>
#include <gdcmTrace.h>
#include <openvdb/Types.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>

namespace gvr {

namespace {

namespace fs = std::filesystem;
using openvdb::Vec3d;

struct SliceHeader {
    std::string file;
    Vec3d position;  // ImagePositionPatient, LPS mm
    bool hasPosition = false;
    double along = 0;  // position projected on the slice normal
    double intercept = 0;
    double slope = 1;
};

struct SeriesHeader {
    unsigned columns = 0, rows = 0, samplesPerPixel = 1;
    SampleType type = SampleType::Int16;
    Vec3d rowDirection, columnDirection;
    double columnSpacing = 1, rowSpacing = 1;  // mm between columns, between rows
    std::string modality = "unknown";
    std::string seriesUid;
    std::optional<std::int64_t> paddingStored;  ///< Pixel Padding Value, as stored
    std::vector<SliceHeader> slices;
};

std::string stringElement(const gdcm::DataSet& dataSet, const gdcm::Tag& tag) {
    if (!dataSet.FindDataElement(tag)) return "";
    const gdcm::ByteValue* value = dataSet.GetDataElement(tag).GetByteValue();
    if (!value) return "";
    std::string text(value->GetPointer(), value->GetLength());
    const auto end = text.find_last_not_of(std::string(" \0", 2));
    return end == std::string::npos ? "" : text.substr(0, end + 1);
}

/// Pixel Padding Value (0028,0120): the stored value of the voxels outside the
/// scanner's field of view (-2000 in the chest, -3024 HU once rescaled). Its VR is
/// US or SS, as the pixels are unsigned or signed.
std::optional<std::int64_t> paddingValueOf(const gdcm::File& dicom, const gdcm::PixelFormat& format) {
    const gdcm::Tag tag(0x0028, 0x0120);
    const gdcm::DataSet& dataSet = dicom.GetDataSet();
    if (!dataSet.FindDataElement(tag)) return std::nullopt;
    const gdcm::ByteValue* value = dataSet.GetDataElement(tag).GetByteValue();
    if (!value || value->GetLength() != 2) return std::nullopt;
    const bool bigEndian = dicom.GetHeader().GetDataSetTransferSyntax().GetSwapCode() == gdcm::SwapCode::BigEndian;
    const std::uint16_t stored = loadWord<std::uint16_t>(value->GetPointer(), bigEndian);
    return format.GetPixelRepresentation() == 1 ? std::int64_t(std::int16_t(stored)) : std::int64_t(stored);
}

SampleType sampleTypeOf(const gdcm::PixelFormat& format, const std::string& file) {
    const bool isSigned = format.GetPixelRepresentation() == 1;
    switch (format.GetBitsAllocated()) {
        case 8:
            return isSigned ? SampleType::Int8 : SampleType::UInt8;
        case 16:
            return isSigned ? SampleType::Int16 : SampleType::UInt16;
        case 32:
            return isSigned ? SampleType::Int32 : SampleType::UInt32;
        default:
            break;
    }
    throw InputError(
        file, "unsupported DICOM pixel format: " + std::to_string(format.GetBitsAllocated()) + " bits allocated");
}

Vec3d vec3(const std::vector<double>& values, std::size_t offset) {
    return Vec3d(values.at(offset), values.at(offset + 1), values.at(offset + 2));
}

/// A negative or zero spacing would mirror or collapse the image without a word.
void checkSpacing(const std::vector<double>& spacing, const std::string& file) {
    if (spacing.size() < 2 || !(spacing[0] > 0.0 && spacing[1] > 0.0) || !std::isfinite(spacing[0] * spacing[1])) {
        throw InputError(file, "PixelSpacing must be two positive numbers");
    }
}

/// Grey, or RGB stored as RGB: a palette's indices or YCbCr values read as they
/// stand would be the wrong picture.
void checkPhotometric(const gdcm::DataSet& dataSet, const std::string& file) {
    const std::string photometric = stringElement(dataSet, gdcm::Tag(0x0028, 0x0004));
    if (photometric.empty() || photometric == "MONOCHROME1" || photometric == "MONOCHROME2" || photometric == "RGB")
        return;
    // Compressed YBR is turned into RGB by the decoder; stored as it is, it is not.
    const bool compressedYbr = photometric.rfind("YBR_", 0) == 0 && photometric != "YBR_FULL";
    if (compressedYbr) return;
    throw InputError(file, "PhotometricInterpretation " + photometric +
                               " is not supported (gvr reads MONOCHROME1/2 and RGB; convert the series, e.g. with "
                               "gdcmconv --raw)");
}

/// An element that must hold a finite decimal string when present.
void checkFiniteText(const gdcm::DataSet& dataSet, const gdcm::Tag& tag, const std::string& name,
                     const std::string& file) {
    const std::string text = stringElement(dataSet, tag);
    if (text.empty()) return;
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !std::isfinite(value)) {
        throw InputError(file, name + " '" + text + "' is not a finite number");
    }
}

bool sameDirections(const std::vector<double>& cosines, const SeriesHeader& series) {
    constexpr double kTolerance = 1e-4;
    return (vec3(cosines, 0) - series.rowDirection).length() < kTolerance &&
           (vec3(cosines, 3) - series.columnDirection).length() < kTolerance;
}

/// Reads one slice's header; the pixel data is skipped.
SliceHeader readSliceHeader(const std::string& file, SeriesHeader& series, bool first) {
    checkDicomStructure(file);
    gdcm::Reader reader;
    reader.SetFileName(file.c_str());
    if (!reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010))) {
        throw InputError(file, "corrupt DICOM header (GDCM could not parse it)");
    }
    const gdcm::File& dicom = reader.GetFile();
    const gdcm::DataSet& dataSet = dicom.GetDataSet();
    const std::vector<unsigned> dims = gdcm::ImageHelper::GetDimensionsValue(dicom);
    const gdcm::PixelFormat format = gdcm::ImageHelper::GetPixelFormatValue(dicom);
    const std::vector<double> cosines = gdcm::ImageHelper::GetDirectionCosinesValue(dicom);
    const std::vector<double> spacing = gdcm::ImageHelper::GetSpacingValue(dicom);
    if (dims.size() < 2 || dims[0] == 0 || dims[1] == 0) {
        throw InputError(file, "DICOM header has no image dimensions");
    }
    if (dims.size() > 2 && dims[2] > 1) {
        throw InputError(file,
                         "multi-frame DICOM files are not supported; gvr reads series "
                         "of single-frame slices");
    }

    checkSpacing(spacing, file);
    checkPhotometric(dataSet, file);
    SliceHeader slice;
    slice.file = file;
    slice.hasPosition = dataSet.FindDataElement(gdcm::Tag(0x0020, 0x0032));
    slice.position = vec3(gdcm::ImageHelper::GetOriginValue(dicom), 0);
    const std::vector<double> rescale = gdcm::ImageHelper::GetRescaleInterceptSlopeValue(dicom);
    slice.intercept = rescale.at(0);
    slice.slope = rescale.at(1);
    // GDCM takes an unreadable slope for 1: the text itself must be a finite number.
    checkFiniteText(dataSet, gdcm::Tag(0x0028, 0x1052), "RescaleIntercept", file);
    checkFiniteText(dataSet, gdcm::Tag(0x0028, 0x1053), "RescaleSlope", file);

    const std::string uid = stringElement(dataSet, gdcm::Tag(0x0020, 0x000e));
    if (first) {
        series.columns = dims[0];
        series.rows = dims[1];
        series.samplesPerPixel = format.GetSamplesPerPixel();
        series.type = sampleTypeOf(format, file);
        series.rowDirection = vec3(cosines, 0);
        series.columnDirection = vec3(cosines, 3);
        series.columnSpacing = spacing.at(0);
        series.rowSpacing = spacing.at(1);
        series.seriesUid = uid;
        const std::string modality = stringElement(dataSet, gdcm::Tag(0x0008, 0x0060));
        if (!modality.empty()) series.modality = modality;
        series.paddingStored = paddingValueOf(dicom, format);
    } else if (dims[0] != series.columns || dims[1] != series.rows) {
        throw InputError(file, "slice is " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) +
                                   " but the series is " + std::to_string(series.columns) + "x" +
                                   std::to_string(series.rows));
    } else if (!sameDirections(cosines, series) || spacing.at(0) != series.columnSpacing ||
               spacing.at(1) != series.rowSpacing) {
        throw InputError(file,
                         "ImageOrientationPatient or PixelSpacing differs from the series' first slice; "
                         "gvr stacks slices of one geometry");
    } else if (uid != series.seriesUid) {
        throw InputError(file, "belongs to another series (SeriesInstanceUID " + uid + "); put one series per folder");
    } else if (sampleTypeOf(format, file) != series.type || format.GetSamplesPerPixel() != series.samplesPerPixel) {
        throw InputError(file, "pixel format differs from the rest of the series");
    }
    if (series.samplesPerPixel != 1 && series.samplesPerPixel != 3) {
        throw InputError(file, "unsupported DICOM samples per pixel: " + std::to_string(series.samplesPerPixel));
    }
    return slice;
}

SeriesHeader readSeriesHeader(const std::string& folder) {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (entry.is_regular_file() && isDicomFile(entry.path().string())) files.push_back(entry.path());
    }
    if (files.empty()) throw InputError(folder, "folder holds no DICOM files");
    std::sort(files.begin(), files.end());

    SeriesHeader series;
    for (const std::string& file : files) {
        series.slices.push_back(readSliceHeader(file, series, series.slices.empty()));
    }
    const Vec3d normal = series.rowDirection.cross(series.columnDirection);
    if (normal.length() < 0.5) {
        throw InputError(files.front(), "ImageOrientationPatient is missing or degenerate");
    }
    for (SliceHeader& slice : series.slices) {
        if (series.slices.size() > 1 && !slice.hasPosition) {
            throw InputError(slice.file, "has no ImagePositionPatient, so its place in the series is unknown");
        }
        slice.along = slice.position.dot(normal);
    }
    std::sort(series.slices.begin(), series.slices.end(),
              [](const SliceHeader& a, const SliceHeader& b) { return a.along < b.along; });
    for (std::size_t s = 1; s < series.slices.size(); ++s) {
        if (std::abs(series.slices[s].along - series.slices[s - 1].along) < 1e-4) {
            throw InputError(series.slices[s].file, "lies at the same position as " + series.slices[s - 1].file);
        }
    }
    return series;
}

/// The step between slices. Taken from first to last position rather than from the
/// normal, so a gantry tilt shows up as a sheared axis.
Vec3d sliceStep(const SeriesHeader& series, DenseVolume& volume) {
    const auto& slices = series.slices;
    if (slices.size() < 2) {
        return series.rowDirection.cross(series.columnDirection);  // 1 mm, as nothing says more
    }
    const std::size_t gaps = slices.size() - 1;
    const Vec3d step = (slices.back().position - slices.front().position) / double(gaps);
    double smallest = INFINITY, largest = 0;
    for (std::size_t s = 1; s < slices.size(); ++s) {
        const double gap = slices[s].along - slices[s - 1].along;
        smallest = std::min(smallest, gap);
        largest = std::max(largest, gap);
    }
    if (largest > 1.1 * smallest) {
        volume.warnings.push_back("slice spacing is not uniform (" + std::to_string(smallest) + " to " +
                                  std::to_string(largest) + " mm); using the mean, positions may be off");
    }
    return step;
}

void setGeometry(const SeriesHeader& series, DenseVolume& volume) {
    const Vec3d origin = series.slices.front().position;
    const Vec3d iAxis = series.rowDirection * series.columnSpacing;
    const Vec3d jAxis = series.columnDirection * series.rowSpacing;
    const Vec3d kAxis = sliceStep(series, volume);
    // DICOM is LPS; gvr's world is RAS like NIfTI, so x and y change sign.
    const double sign[3] = {-1, -1, 1};
    double rows[3][4];
    for (int r = 0; r < 3; ++r) {
        rows[r][0] = sign[r] * iAxis[r];
        rows[r][1] = sign[r] * jAxis[r];
        rows[r][2] = sign[r] * kAxis[r];
        rows[r][3] = sign[r] * origin[r];
    }
    volume.worldFromIndex = worldFromIndexRows(rows);
}

bool rescaleIsUniform(const SeriesHeader& series) {
    const SliceHeader& first = series.slices.front();
    return std::all_of(series.slices.begin(), series.slices.end(),
                       [&](const SliceHeader& s) { return s.slope == first.slope && s.intercept == first.intercept; });
}

/// GDCM decodes what it can of a cut-off file without complaint, so check that
/// native pixel data holds every byte (checkDicomStructure() has already seen
/// compressed pixel data end with its delimiter).
void checkPixelDataComplete(const gdcm::DataSet& dataSet, const std::string& file, std::size_t storedBytes) {
    const gdcm::Tag pixelData(0x7fe0, 0x0010);
    if (!dataSet.FindDataElement(pixelData)) throw InputError(file, "has no pixel data");
    const gdcm::ByteValue* value = dataSet.GetDataElement(pixelData).GetByteValue();
    if (value && value->GetLength() < storedBytes) {
        throw InputError(file, "truncated: pixel data holds " + std::to_string(value->GetLength()) +
                                   " bytes, expected " + std::to_string(storedBytes));
    }
}

/// Three planes of @a pixels samples of @a bytes each, as RGB triples.
std::vector<char> interleavedFromPlanes(const std::vector<char>& planes, std::size_t pixels, std::size_t bytes) {
    std::vector<char> out(planes.size());
    for (std::size_t p = 0; p < pixels; ++p) {
        for (std::size_t c = 0; c < 3; ++c) {
            std::copy_n(planes.data() + (c * pixels + p) * bytes, bytes, out.data() + (p * 3 + c) * bytes);
        }
    }
    return out;
}

/// Decodes one slice into @a destination, rescaled to float when the series mixes
/// rescale parameters.
void decodeSlice(const SeriesHeader& series, std::size_t index, unsigned char* destination, bool perSliceRescale) {
    const SliceHeader& slice = series.slices[index];
    gdcm::ImageReader reader;
    reader.SetFileName(slice.file.c_str());
    if (!reader.Read()) throw InputError(slice.file, "truncated or undecodable DICOM pixel data");
    const gdcm::Image& image = reader.GetImage();
    const std::size_t samples = std::size_t(series.columns) * series.rows * series.samplesPerPixel;
    const std::size_t storedBytes = samples * bytesPerSample(series.type);
    checkPixelDataComplete(reader.GetFile().GetDataSet(), slice.file, storedBytes);
    if (image.GetBufferLength() != storedBytes) {
        throw InputError(slice.file, "pixel data holds " + std::to_string(image.GetBufferLength()) +
                                         " bytes, expected " + std::to_string(storedBytes));
    }
    std::vector<char> stored(storedBytes);
    if (!image.GetBuffer(stored.data())) {
        throw InputError(slice.file, "truncated or undecodable DICOM pixel data");
    }
    // PlanarConfiguration 1 stores the red plane, then green, then blue.
    if (series.samplesPerPixel == 3 && image.GetPlanarConfiguration() == 1) {
        stored = interleavedFromPlanes(stored, samples / 3, bytesPerSample(series.type));
    }
    if (!perSliceRescale) {
        std::copy(stored.begin(), stored.end(), reinterpret_cast<char*>(destination));
        return;
    }
    float* out = reinterpret_cast<float*>(destination);
    dispatchSampleType(series.type, [&](auto sample) {
        using T = decltype(sample);
        const T* in = reinterpret_cast<const T*>(stored.data());
        for (std::size_t s = 0; s < samples; ++s) out[s] = float(slice.slope * in[s] + slice.intercept);
    });
}

class DicomSeries : public SliceSource {
public:
    DicomSeries(DenseVolume layout, const std::string& folder, SeriesHeader series, bool perSliceRescale)
        : SliceSource(std::move(layout), folder), mSeries(std::move(series)), mPerSliceRescale(perSliceRescale) {}

private:
    void readSlices(std::int64_t first, std::int64_t count, unsigned char* destination,
                    const ProgressFn& progress) const override {
        decodeEachSlice(first, count, destination, progress, [this](std::int64_t index, unsigned char* slice) {
            decodeSlice(mSeries, std::size_t(index), slice, mPerSliceRescale);
        });
    }

    SeriesHeader mSeries;
    bool mPerSliceRescale;
};

}  // namespace

bool isDicomFile(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) return false;  // a FIFO would block the read
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.seekg(128);  // the magic follows a 128-byte preamble
    in.read(magic, 4);
    return in && std::string(magic, 4) == "DICM";
}

std::unique_ptr<SliceSource> openDicomSeries(const std::string& folder, const ReadOptions&) {
    // GDCM's warnings and errors would add lines to gvr's one-line messages; the
    // checks here report what matters about a file, in that one line.
    gdcm::Trace::WarningOff();
    gdcm::Trace::ErrorOff();
    SeriesHeader series = readSeriesHeader(folder);
    DenseVolume layout;
    layout.dims = {series.columns, series.rows, std::int64_t(series.slices.size())};
    layout.channels = int(series.samplesPerPixel);
    layout.modality = series.modality;
    checkDimensions(folder, layout.dims);
    setGeometry(series, layout);

    const bool perSliceRescale = !rescaleIsUniform(series);
    layout.type = perSliceRescale ? SampleType::Float32 : series.type;
    if (!perSliceRescale) {
        layout.slope = series.slices.front().slope;
        layout.intercept = series.slices.front().intercept;
        // Slices rescaled alike share one physical padding value; others have none.
        if (series.paddingStored)
            layout.markedPadding = layout.slope * double(*series.paddingStored) + layout.intercept;
    }
    return std::make_unique<DicomSeries>(std::move(layout), folder, std::move(series), perSliceRescale);
}

}  // namespace gvr
