// What gvr opens as input (regular files only, no NUL bytes in paths), and how
// orbit frames are named: two small rules that many commands lean on.

#include "io/guard/InputFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>

using namespace gvr;

TEST(InputFile, OnlyRegularFilesAreInputsAndEveryRefusalNamesThePath) {
    test::TempDir dir;
    const std::string file = dir.path("scan.raw"), link = dir.path("link.raw"), fifo = dir.path("pipe");
    test::writeBytes(file, "1234");
    std::filesystem::create_symlink(file, link);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { requireRegularFile(file); }), "");
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { requireRegularFile(link); }), "") << "links are followed";
    for (const std::string& path : {dir.path("missing.raw"), dir.path(""), fifo, std::string("/dev/zero")}) {
        const std::string message = test::errorMessageOf<InputError>([&] { requireRegularFile(path); });
        EXPECT_NE(message, "") << path;
        EXPECT_NE(message.find(path), std::string::npos) << message;
    }
    const std::string withNul = file + std::string(1, '\0') + "x";
    EXPECT_NE(test::errorMessageOf<InputError>([&] { requireNoNulByte(withNul); }), "");
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { requireNoNulByte(file); }), "");
}
