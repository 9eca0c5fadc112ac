// The exception types: an input error names its culprit first and stays on one
// line whatever the library's text; a cancellation says what was cancelled.

#include "pipeline/Error.h"

#include <gtest/gtest.h>

#include <string>

namespace gvr {
namespace {

TEST(Error, InputErrorNamesTheCulpritFirstOnOneLine) {
    const InputError error("scan.png", "PNG read error: bad CRC\nPNG library error\r\n");
    EXPECT_EQ(std::string(error.what()), "scan.png: PNG read error: bad CRC; PNG library error");
}

TEST(Error, AWindowsLineBreakIsOneBreak) {
    const InputError error("scan.dcm", "first line\r\nsecond line\rthird line");
    EXPECT_EQ(std::string(error.what()), "scan.dcm: first line; second line; third line");
}

TEST(Error, CancelledSaysWhatStopped) {
    const Cancelled stopped("fit ch2.vdb");
    EXPECT_EQ(std::string(stopped.what()), "fit ch2.vdb: cancelled");
}

}  // namespace
}  // namespace gvr
