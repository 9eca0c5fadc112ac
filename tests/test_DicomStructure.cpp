// The DICOM element walk that runs before GDCM: a file cut inside any element,
// fragment or sequence is refused with one line naming it; a whole file, or one
// whose native pixels alone are short, passes.

#include "io/guard/DicomStructure.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace gvr {
namespace {

const char* const kExplicitLittle = "1.2.840.10008.1.2.1";
const char* const kImplicitLittle = "1.2.840.10008.1.2";
const char* const kDeflated = "1.2.840.10008.1.2.1.99";

std::string tag(std::uint32_t group, std::uint32_t element) {
    return test::littleEndian16(group) + test::littleEndian16(element);
}

/// An explicit-VR element; OB, OW, SQ and UN take a 4-byte length.
std::string explicitElement(std::uint32_t group, std::uint32_t element, const std::string& vr, const std::string& value,
                            std::uint32_t length) {
    const bool longLength = vr == "OB" || vr == "OW" || vr == "SQ" || vr == "UN";
    return tag(group, element) + vr +
           (longLength ? std::string(2, '\0') + test::littleEndian32(length) : test::littleEndian16(length)) + value;
}
std::string explicitElement(std::uint32_t group, std::uint32_t element, const std::string& vr,
                            const std::string& value) {
    return explicitElement(group, element, vr, value, std::uint32_t(value.size()));
}

/// The preamble, "DICM" and a file meta group naming @a transferSyntax.
std::string preambleAndMeta(std::string transferSyntax) {
    if (transferSyntax.size() % 2) transferSyntax.push_back('\0');
    return std::string(128, '\0') + "DICM" + explicitElement(0x0002, 0x0010, "UI", transferSyntax);
}

std::string patientName() { return explicitElement(0x0010, 0x0010, "PN", "Doe^J "); }

std::string errorFor(const test::TempDir& dir, const std::string& bytes) {
    const std::string path = dir.path("slice.dcm");
    test::writeBytes(path, bytes);
    return test::errorMessageOf<InputError>([&] { checkDicomStructure(path); });
}

TEST(DicomStructure, AWholeFilePassesAndACutOneIsRefusedInsideEveryElement) {
    test::TempDir dir;
    const std::string head = preambleAndMeta(kExplicitLittle) + patientName();
    const std::string pixels = explicitElement(0x7fe0, 0x0010, "OW", std::string(8, '\x7f'));
    EXPECT_EQ(errorFor(dir, head + pixels), "");
    const std::string path = dir.path("slice.dcm");
    // Up to the pixel data's value, every cut but the one between two elements fails.
    for (std::size_t keep = 0; keep < head.size() + 12; ++keep) {
        if (keep == head.size()) continue;
        const std::string message = errorFor(dir, (head + pixels).substr(0, keep));
        EXPECT_EQ(message.rfind(path + ": truncated DICOM file", 0), 0u) << "cut at " << keep << ": " << message;
    }
    // Native pixel data may be short: the reader reports by how much.
    EXPECT_EQ(errorFor(dir, (head + pixels).substr(0, head.size() + 12 + 3)), "");
}

TEST(DicomStructure, NothingAfterTheFileMetaIsRefused) {
    test::TempDir dir;
    EXPECT_EQ(errorFor(dir, preambleAndMeta(kExplicitLittle)),
              dir.path("slice.dcm") + ": truncated DICOM file: nothing follows its file meta information");
}

TEST(DicomStructure, CompressedFragmentsMustEndWithTheirDelimiter) {
    test::TempDir dir;
    const std::string head = preambleAndMeta("1.2.840.10008.1.2.4.50") + patientName();
    const std::string fragments = explicitElement(0x7fe0, 0x0010, "OB", "", 0xffffffffu) + tag(0xfffe, 0xe000) +
                                  test::littleEndian32(0) +                                 // empty offset table
                                  tag(0xfffe, 0xe000) + test::littleEndian32(4) + "JPEG" +  // one fragment
                                  tag(0xfffe, 0xe0dd) + test::littleEndian32(0);            // the delimiter
    const std::string whole = head + fragments;
    EXPECT_EQ(errorFor(dir, whole), "");
    // Cut anywhere after the pixel data's tag starts: in a fragment, or before the delimiter.
    for (std::size_t keep = head.size() + 1; keep < whole.size(); ++keep) {
        EXPECT_NE(errorFor(dir, whole.substr(0, keep)), "") << "cut at " << keep << " of " << whole.size();
    }
}

TEST(DicomStructure, AnElementLongerThanItsSequenceIsRefused) {
    test::TempDir dir;
    // A 10-byte sequence whose item claims 100 bytes: inside the file, but not inside its parent.
    const std::string item = tag(0xfffe, 0xe000) + test::littleEndian32(100) + "ab";
    const std::string sequence = explicitElement(0x0008, 0x1115, "SQ", item);
    const std::string bytes = preambleAndMeta(kExplicitLittle) + sequence + patientName() + std::string(200, ' ');
    EXPECT_EQ(errorFor(dir, bytes), dir.path("slice.dcm") + ": truncated DICOM file: it ends inside an element");
}

TEST(DicomStructure, SequencesNestedTooDeeplyAreRefusedNotRecursedInto) {
    test::TempDir dir;
    std::string nested = preambleAndMeta(kExplicitLittle);
    for (int level = 0; level < 40; ++level) {
        nested += explicitElement(0x0008, 0x1115, "SQ", "", 0xffffffffu) + tag(0xfffe, 0xe000) +
                  test::littleEndian32(0xffffffffu);
    }
    EXPECT_EQ(errorFor(dir, nested), dir.path("slice.dcm") + ": corrupt DICOM header: sequences nested too deeply");
}

TEST(DicomStructure, ImplicitVrLengthsAreReadWithoutAVr) {
    test::TempDir dir;
    const std::string head = preambleAndMeta(kImplicitLittle);
    const std::string name = tag(0x0010, 0x0010) + test::littleEndian32(6) + "Doe^J ";
    const std::string pixels = tag(0x7fe0, 0x0010) + test::littleEndian32(8) + std::string(8, '\0');
    EXPECT_EQ(errorFor(dir, head + name + pixels), "");
    // Read as explicit VR, "\x06\0" would be the VR: the length must come from the 4 bytes.
    const std::string tooLong = tag(0x0010, 0x0010) + test::littleEndian32(600) + "Doe^J ";
    EXPECT_EQ(errorFor(dir, head + tooLong + pixels),
              dir.path("slice.dcm") + ": truncated DICOM file: it ends inside an element");
}

TEST(DicomStructure, ADeflatedDataSetIsCheckedOnlyUpToItsMeta) {
    test::TempDir dir;
    // GDCM inflates it first; the walk cannot read compressed elements.
    EXPECT_EQ(errorFor(dir, preambleAndMeta(kDeflated) + std::string("\x78\x9c", 2) + std::string(30, '\x01')), "");
    // A cut meta group is still refused.
    const std::string meta = preambleAndMeta(kDeflated);
    EXPECT_NE(errorFor(dir, meta.substr(0, meta.size() - 3)), "");
}

}  // namespace
}  // namespace gvr
