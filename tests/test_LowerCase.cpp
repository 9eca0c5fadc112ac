// Case-folding of names users type: only ASCII letters change, and suffix tests
// ignore case on both sides.

#include "pipeline/LowerCase.h"

#include <gtest/gtest.h>

#include <string>

namespace gvr {
namespace {

TEST(LowerCase, FoldsAsciiLettersOnly) {
    EXPECT_EQ(lowerCase("Scan.NII.GZ"), "scan.nii.gz");
    EXPECT_EQ(lowerCase("A1-Z9_[]"), "a1-z9_[]");
    EXPECT_EQ(lowerCase(""), "");
}

TEST(LowerCase, LeavesNonAsciiBytesAlone) {
    // UTF-8 "Ä" is two bytes above 127; the cast to unsigned char must keep tolower from seeing negatives.
    const std::string text = "\xC3\x84X";
    EXPECT_EQ(lowerCase(text), "\xC3\x84x");
}

TEST(LowerCase, EndsWithIgnoringCase) {
    EXPECT_TRUE(endsWithIgnoringCase("brain.NII.gz", ".nii.GZ"));
    EXPECT_TRUE(endsWithIgnoringCase("x.vdb", ""));
    EXPECT_TRUE(endsWithIgnoringCase(".VDB", ".vdb"));
    EXPECT_FALSE(endsWithIgnoringCase("x.vdb.bak", ".vdb"));
    // A suffix longer than the text must not read before its start.
    EXPECT_FALSE(endsWithIgnoringCase("vdb", ".vdb"));
    EXPECT_FALSE(endsWithIgnoringCase("", "a"));
}

}  // namespace
}  // namespace gvr
