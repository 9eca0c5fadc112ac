// Label style files: styles are read by the key as written, and every mistake is
// refused with the file, the structure and the rule it broke.

#include "io/formats/LabelStyleFile.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <fstream>
#include <utility>

using namespace gvr;

TEST(LabelStyleFile, ReadsStylesAndRefusesMistakes) {
    test::TempDir dir;
    const auto write = [&](const std::string& text) {
        std::ofstream(dir.path("s.json")) << text;
        return dir.path("s.json");
    };
    const auto styles = readLabelStyles(write(R"({"Thalamus_L": {"color": [1, 0, 0]}, "37": {"opacity": 0.25}})"));
    ASSERT_EQ(styles.size(), 2u);
    EXPECT_EQ(styles.at("Thalamus_L").colour, (std::array<float, 3>{1, 0, 0}));
    EXPECT_EQ(styles.at("Thalamus_L").opacity, 1.0f);
    EXPECT_FALSE(styles.at("37").colour);
    EXPECT_EQ(styles.at("37").opacity, 0.25f);

    for (const char* bad :
         {R"({"x": {"color": [1, 0]}})", R"({"x": {"color": [2, 0, 0]}})", R"({"x": {"opacity": -1}})",
          R"({"x": {"colour": [1, 0, 0]}})", R"({"x": 3})", "[1, 2]", "{oops"}) {
        EXPECT_THROW(readLabelStyles(write(bad)), InputError) << bad;
    }
    EXPECT_THROW(readLabelStyles(dir.path("missing.json")), InputError);
}

TEST(LabelStyleFile, OpacityBoundsAreInclusive) {
    test::TempDir dir;
    const std::string path = dir.path("s.json");
    test::writeBytes(
        path, R"({"clear": {"opacity": 0}, "loud": {"opacity": 1000}, "both": {"color": [0, 1, 0.5], "opacity": 3}})");
    const auto styles = readLabelStyles(path);
    ASSERT_EQ(styles.size(), 3u);
    EXPECT_EQ(styles.at("clear").opacity, 0.0f);
    EXPECT_EQ(styles.at("loud").opacity, 1000.0f);
    EXPECT_EQ(styles.at("both").colour, (std::array<float, 3>{0.0f, 1.0f, 0.5f}));
    EXPECT_EQ(styles.at("both").opacity, 3.0f);
}

TEST(LabelStyleFile, MessagesNameTheFileTheStructureAndTheRule) {
    test::TempDir dir;
    const std::string path = dir.path("s.json");
    const std::pair<const char*, const char*> bad[] = {
        {R"({"Amygdala_R": {"opacity": 1000.5}})", "structure 'Amygdala_R': opacity must be a number in [0, 1000]"},
        // Far beyond float: refused before the cast.
        {R"({"12": {"opacity": 1e300}})", "structure '12': opacity must be a number in [0, 1000]"},
        {R"({"12": {"opacity": "half"}})", "structure '12': opacity must be a number in [0, 1000]"},
        {R"({"x": {"color": [0, -0.01, 0]}})", "structure 'x': color components must lie in [0, 1]"},
        {R"({"x": {"color": [0, "1", 0]}})", "structure 'x': color components must lie in [0, 1]"},
        {R"({"x": {"color": [1, 0, 0, 1]}})", "structure 'x': color must be [r, g, b]"},
        {R"({"x": {"colour": [1, 0, 0]}})", "structure 'x': unknown key 'colour' (color, opacity)"},
        {R"({"x": [1, 0, 0]})", "structure 'x': expected {"},
        {R"({"x": {"opacity": NaN}})", "not a JSON object of structure styles"},
    };
    for (const auto& [text, problem] : bad) {
        test::writeBytes(path, text);
        const std::string message = test::errorMessageOf<InputError>([&] { readLabelStyles(path); });
        EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
        EXPECT_NE(message.find(problem), std::string::npos) << text << " gave: " << message;
    }
}

TEST(LabelStyleFile, AnEmptyObjectMeansNoStyles) {
    test::TempDir dir;
    test::writeBytes(dir.path("s.json"), "{}");
    EXPECT_TRUE(readLabelStyles(dir.path("s.json")).empty());
}
