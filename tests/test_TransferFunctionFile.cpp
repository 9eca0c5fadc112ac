// Transfer function files: what the reader accepts and refuses, and that the
// writer's output reads back as the same function.

#include "io/formats/TransferFunctionFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <utility>

namespace gvr {
namespace {

TEST(TransferFunctionFile, ReadsPointsAndRejectsBadOnes) {
    test::TempDir dir;
    test::writeBytes(dir.path("ok.json"), R"({"points": [[-100, 0, 0, 0, 0], [100, 1, 0.5, 0.25, 1]]})");
    const TransferFunction tf = readTransferFunction(dir.path("ok.json"));
    const auto middle = tf(0.0);
    EXPECT_FLOAT_EQ(middle[0], 0.5f);
    EXPECT_FLOAT_EQ(middle[1], 0.25f);
    EXPECT_FLOAT_EQ(middle[3], 0.5f);
    EXPECT_EQ(tf(-1e9)[3], 0.0f);
    EXPECT_EQ(tf(1e9)[3], 1.0f);
    const std::pair<const char*, const char*> bad[] = {
        {"notjson.json", "{points"},
        {"empty.json", R"({"points": []})"},
        {"short.json", R"({"points": [[0, 1, 1, 1]]})"},
        {"order.json", R"({"points": [[5, 0, 0, 0, 0], [5, 1, 1, 1, 1]]})"},
        {"range.json", R"({"points": [[0, 0, 0, 0, 1.5]]})"},
    };
    for (const auto& [name, text] : bad) {
        test::writeBytes(dir.path(name), text);
        try {
            readTransferFunction(dir.path(name));
            ADD_FAILURE() << name << " was accepted";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
        }
    }
}

TEST(TransferFunctionFile, EveryRefusalNamesTheFileAndTheProblem) {
    test::TempDir dir;
    const std::pair<const char*, const char*> bad[] = {
        {R"([[0, 0, 0, 0, 0]])", "expected {\"points\""},
        {R"({"pts": [[0, 0, 0, 0, 0]]})", "expected {\"points\""},
        {R"({"points": [[0, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0]]})", "point 1 is not [value, r, g, b, a]"},
        {R"({"points": [[0, "red", 0, 0, 0]]})", "point 0 is not [value, r, g, b, a]"},
        // Far outside float's range: checked as a double before any cast.
        {R"({"points": [[0, 0, 0, 0, 1e300]]})", "point 0: colour and opacity must lie in [0, 1]"},
        {R"({"points": [[0, 0, 0, -0.001, 0]]})", "point 0: colour and opacity must lie in [0, 1]"},
        {R"({"points": [[NaN, 0, 0, 0, 0]]})", "not valid JSON"},  // JSON has no NaN
    };
    const std::string path = dir.path("tf.json");
    for (const auto& [text, problem] : bad) {
        test::writeBytes(path, text);
        const std::string message = test::errorMessageOf<InputError>([&] { readTransferFunction(path); });
        EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << text << " gave: " << message;
    }
    const std::string missing = test::errorMessageOf<InputError>([&] { readTransferFunction(dir.path("none.json")); });
    EXPECT_NE(missing.find(dir.path("none.json")), std::string::npos) << missing;
}

TEST(TransferFunctionFile, WhatIsWrittenReadsBackExactly) {
    test::TempDir dir;
    // Values and channels that decimal printing could round: they must survive to the bit.
    const TransferFunction tf({{-1024.1, {0.0f, 0.1f, 0.2f, 0.0f}},
                               {0.3, {1.0f / 3.0f, 0.7f, 0.9f, 0.05f}},
                               {3071.999999, {1.0f, 1.0f, 1.0f, 1.0f}}},
                              "tf");
    const std::string path = dir.path("tf.json");
    test::writeBytes(path, "an older file");
    writeTransferFunction(path, tf);
    const TransferFunction back = readTransferFunction(path);
    ASSERT_EQ(back.points().size(), 3u);
    for (std::size_t n = 0; n < 3; ++n) {
        EXPECT_EQ(back.points()[n].value, tf.points()[n].value) << n;
        EXPECT_EQ(back.points()[n].rgba, tf.points()[n].rgba) << n;
    }
    // Only the file: the atomic write left no temporary beside it.
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.root()), {}), 1);
}

TEST(TransferFunctionFile, AWriteIntoAMissingFolderThrowsAndCreatesNothing) {
    test::TempDir dir;
    const TransferFunction tf({{0.0, {0, 0, 0, 0}}}, "tf");
    EXPECT_THROW(writeTransferFunction(dir.path("missing/tf.json"), tf), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir.path("missing")));
}

}  // namespace
}  // namespace gvr
