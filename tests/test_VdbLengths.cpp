// The walk of a VDB file's lengths before OpenVDB reads it: a good file passes, and
// every truncation and an old format are refused naming the file.

#include "io/formats/GridFile.h"
#include "io/guard/VdbLengths.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace gvr {
namespace {

std::string writtenGrid(const test::TempDir& dir) {
    const std::string path = dir.path("grid.vdb");
    writeGridFile(path,
                  {test::makeGrid({20, 18, 9}, [](int i, int j, int k) { return float(std::sin(0.3 * i) * j + k); })});
    return path;
}

TEST(VdbLengths, AWrittenGridPasses) {
    test::TempDir dir;
    EXPECT_NO_THROW(checkVdbLengths(writtenGrid(dir)));
}

TEST(VdbLengths, EveryTruncationIsRefusedNamingTheFile) {
    test::TempDir dir;
    const std::string good = writtenGrid(dir);
    const std::size_t size = test::readBytes(good).size();
    const std::string cut = dir.path("cut.vdb");
    for (std::size_t keep = 0; keep < size; keep += std::max<std::size_t>(1, size / 97)) {
        test::copyTruncated(good, cut, keep);
        const std::string message = test::errorMessageOf<InputError>([&] { checkVdbLengths(cut); });
        EXPECT_NE(message.find(cut), std::string::npos) << "kept " << keep << " of " << size << " bytes: " << message;
    }
}

TEST(VdbLengths, AFormatBeforeOpenVdb3IsRefused) {
    test::TempDir dir;
    std::string bytes = test::readBytes(writtenGrid(dir));
    const std::uint32_t old = 221;  // the file version follows the 8-byte magic
    std::memcpy(&bytes[8], &old, sizeof(old));
    const std::string path = dir.path("old.vdb");
    test::writeBytes(path, bytes);
    const std::string message = test::errorMessageOf<InputError>([&] { checkVdbLengths(path); });
    EXPECT_NE(message.find("format version 221"), std::string::npos) << message;
}

}  // namespace
}  // namespace gvr
