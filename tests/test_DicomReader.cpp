// DICOM series that would be read as the wrong picture are read correctly or refused
// naming the slice: mixed geometry, mirrored spacing, unreadable rescale text, a
// missing position, palette colour, and RGB stored plane by plane.

#include "io/formats/Readers.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gdcmImageWriter.h>
#include <gdcmReader.h>
#include <gdcmUIDGenerator.h>
#include <gdcmWriter.h>
#include <gtest/gtest.h>

#include <filesystem>

namespace gvr {
namespace {

constexpr const char* kSlices[] = {"1-001.dcm", "1-002.dcm", "1-003.dcm"};

/// Three real chest slices in @a folder, the second changed by @a change.
void writeSeries(const test::TempDir& dir, const std::string& folder, const std::function<void(gdcm::DataSet&)>& change,
                 bool changeAll = false) {
    std::filesystem::create_directory(dir.path(folder));
    for (int s = 0; s < 3; ++s) {
        gdcm::Reader reader;
        const std::string from = test::sharedData(std::string("ct-chest-ricord-512/") + kSlices[s]);
        reader.SetFileName(from.c_str());
        ASSERT_TRUE(reader.Read()) << from;
        if (s == 1 || changeAll) change(reader.GetFile().GetDataSet());
        gdcm::Writer writer;
        writer.SetFile(reader.GetFile());
        const std::string to = dir.path(folder + "/" + kSlices[s]);
        writer.SetFileName(to.c_str());
        ASSERT_TRUE(writer.Write()) << to;
    }
}

std::function<void(gdcm::DataSet&)> setText(std::uint16_t group, std::uint16_t element, const std::string& text) {
    return [=](gdcm::DataSet& dataSet) {
        gdcm::DataElement value(gdcm::Tag(group, element));
        std::string even = text.size() % 2 ? text + " " : text;
        value.SetByteValue(even.c_str(), gdcm::VL(std::uint32_t(even.size())));
        if (dataSet.FindDataElement(value.GetTag())) value.SetVR(dataSet.GetDataElement(value.GetTag()).GetVR());
        dataSet.Replace(value);
    };
}

std::string readError(const std::string& folder) {
    try {
        readVolume(folder, {});
    } catch (const InputError& error) {
        return error.what();
    }
    return "read without complaint";
}

TEST(DicomReader, SeriesThatWouldBeReadWrongAreRefusedNamingTheSlice) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    struct Case {
        std::string name;
        std::function<void(gdcm::DataSet&)> change;
        std::string expected;
        bool changeAll = false;
    };
    const std::vector<Case> cases = {
        {"tilted", setText(0x0020, 0x0037, "1\\0\\0\\0\\0.8\\0.6"),
         "1-002.dcm: ImageOrientationPatient or PixelSpacing differs"},
        {"finer", setText(0x0028, 0x0030, "0.5\\0.5"), "1-002.dcm: ImageOrientationPatient or PixelSpacing differs"},
        {"mirrored", setText(0x0028, 0x0030, "-0.703125\\-0.703125"), "PixelSpacing must be two positive numbers"},
        {"nanslope", setText(0x0028, 0x1053, "nan"), "1-002.dcm: RescaleSlope 'nan' is not a finite number"},
        {"nowhere", [](gdcm::DataSet& d) { d.Remove(gdcm::Tag(0x0020, 0x0032)); },
         "1-002.dcm: has no ImagePositionPatient"},
        {"palette", setText(0x0028, 0x0004, "PALETTE COLOR"),
         "PhotometricInterpretation PALETTE COLOR is not supported", true},
    };
    for (const Case& c : cases) {
        writeSeries(dir, c.name, c.change, c.changeAll);
        const std::string message = readError(dir.path(c.name));
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
    }
}

/// A two-slice 8-bit RGB series of 4 x 3 pixels, stored plane by plane when @a planar.
void writeRgbSeries(const std::string& folder, bool planar) {
    std::filesystem::create_directory(folder);
    gdcm::UIDGenerator uids;
    const std::string series = uids.Generate();
    for (int s = 0; s < 2; ++s) {
        gdcm::ImageWriter writer;
        gdcm::Image& image = writer.GetImage();
        image.SetNumberOfDimensions(2);
        image.SetDimension(0, 4);
        image.SetDimension(1, 3);
        image.SetPixelFormat(gdcm::PixelFormat(3, 8, 8, 7, 0));
        image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::RGB);
        image.SetPlanarConfiguration(planar ? 1 : 0);
        const double origin[3] = {0.0, 0.0, 2.0 * s}, cosines[6] = {1, 0, 0, 0, 1, 0}, spacing[3] = {1, 1, 2};
        image.SetOrigin(origin);
        image.SetDirectionCosines(cosines);
        image.SetSpacing(spacing);
        std::vector<char> pixels(4 * 3 * 3);
        for (int p = 0; p < 12; ++p) {
            for (int c = 0; c < 3; ++c) {
                const char value = char(10 * p + c + 100 * s);
                pixels[planar ? std::size_t(c * 12 + p) : std::size_t(p * 3 + c)] = value;
            }
        }
        gdcm::DataElement data(gdcm::Tag(0x7fe0, 0x0010));
        data.SetByteValue(pixels.data(), gdcm::VL(std::uint32_t(pixels.size())));
        image.SetDataElement(data);
        gdcm::DataSet& dataSet = writer.GetFile().GetDataSet();
        setText(0x0020, 0x000e, series)(dataSet);
        setText(0x0008, 0x0016, "1.2.840.10008.5.1.4.1.1.2")(dataSet);  // CT image storage: it has a position
        setText(0x0008, 0x0018, uids.Generate())(dataSet);
        const std::string file = folder + "/s" + std::to_string(s) + ".dcm";
        writer.SetFileName(file.c_str());
        ASSERT_TRUE(writer.Write()) << file;
        // The image writer keeps no z of a 2D image's origin: the slice's place is set afterwards.
        gdcm::Reader reader;
        reader.SetFileName(file.c_str());
        ASSERT_TRUE(reader.Read());
        setText(0x0020, 0x0032, "0\\0\\" + std::to_string(2 * s))(reader.GetFile().GetDataSet());
        gdcm::Writer placed;
        placed.SetFile(reader.GetFile());
        placed.SetFileName(file.c_str());
        ASSERT_TRUE(placed.Write()) << file;
    }
}

TEST(DicomReader, RgbStoredPlaneByPlaneReadsAsRgbStoredInterleaved) {
    test::TempDir dir;
    writeRgbSeries(dir.path("interleaved"), false);
    writeRgbSeries(dir.path("planar"), true);
    const DenseVolume interleaved = readVolume(dir.path("interleaved"), {});
    const DenseVolume planar = readVolume(dir.path("planar"), {});
    ASSERT_EQ(interleaved.channels, 3);
    ASSERT_EQ(interleaved.samples.size(), 4u * 3 * 2 * 3);
    EXPECT_EQ(planar.samples, interleaved.samples);
    EXPECT_EQ(interleaved.samples[3 * 5 + 1], 10 * 5 + 1);  // pixel 5's green, slice 0
}

}  // namespace
}  // namespace gvr
