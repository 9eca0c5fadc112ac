// Label styles: a style recolours and rescales a transfer function (style files: test_LabelStyleFile.cpp).

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
