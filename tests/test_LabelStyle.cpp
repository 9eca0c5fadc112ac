// Label styles: a style recolours and rescales a transfer function; style files are checked.

#include "io/LabelStyleFile.h"
#include "pipeline/Error.h"
#include "pipeline/LabelStyle.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <fstream>

using namespace gvr;

TEST(LabelStyle, RecoloursEveryPointAndScalesOpacityUpToOne) {
    const TransferFunction base({{0.0, {0, 0, 0, 0}}, {100.0, {1, 1, 1, 0.4f}}, {200.0, {1, 0.9f, 0.8f, 0.9f}}}, "t");
    LabelStyle style;
    style.colour = std::array<float, 3>{0.2f, 0.4f, 1.0f};
    style.opacity = 2.0f;
    const TransferFunction styled = styledTransferFunction(base, style);
    ASSERT_EQ(styled.points().size(), 3u);
    EXPECT_EQ(styled(100.0), (std::array<float, 4>{0.2f, 0.4f, 1.0f, 0.8f}));
    EXPECT_EQ(styled(200.0)[3], 1.0f);  // 1.8 clamped
    EXPECT_EQ(styled(0.0)[3], 0.0f);    // still transparent where the base is
    EXPECT_EQ(styled.transparentUpTo(), base.transparentUpTo());

    LabelStyle fadeOnly;
    fadeOnly.opacity = 0.5f;
    EXPECT_EQ(styledTransferFunction(base, fadeOnly)(200.0), (std::array<float, 4>{1, 0.9f, 0.8f, 0.45f}));
}

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

    for (const char* bad : {R"({"x": {"color": [1, 0]}})", R"({"x": {"color": [2, 0, 0]}})", R"({"x": {"opacity": -1}})",
                            R"({"x": {"colour": [1, 0, 0]}})", R"({"x": 3})", "[1, 2]", "{oops"}) {
        EXPECT_THROW(readLabelStyles(write(bad)), InputError) << bad;
    }
    EXPECT_THROW(readLabelStyles(dir.path("missing.json")), InputError);
}
