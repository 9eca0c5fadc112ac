// The flags that gvr render and gvr view share: --stacks by name only, --reuse-angle,
// and --size as WIDTHxHEIGHT within the camera's limit.

#include "cli/RenderFlags.h"
#include "pipeline/Error.h"
#include "render/Camera.h"
#include "tests/ParseFlags.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace gvr {
namespace {

TEST(RenderFlags, StacksAndReuseAngleReachTheSettings) {
    ShearWarpSettings settings;
    CLI::App app;
    addStackFlags(app, settings);
    test::parseFlags(app, {"--stacks", "view", "--reuse-angle", "25"});
    EXPECT_EQ(settings.stacks, StackOrientation::View);
    EXPECT_EQ(settings.reuseAngleDeg, 25.0);

    ShearWarpSettings back;
    back.stacks = StackOrientation::View;
    CLI::App again;
    addStackFlags(again, back);
    test::parseFlags(again, {"--stacks", "axes"});
    EXPECT_EQ(back.stacks, StackOrientation::Axes);
}

TEST(RenderFlags, WithoutFlagsTheSettingsKeepTheirDefaultsAndHelpShowsThem) {
    ShearWarpSettings settings;
    CLI::App app;
    addStackFlags(app, settings);
    test::parseFlags(app, {});
    EXPECT_EQ(settings.stacks, StackOrientation::Axes);
    EXPECT_EQ(settings.reuseAngleDeg, 15.0);
    EXPECT_EQ(app.get_option("--stacks")->get_default_str(), "axes");
    EXPECT_EQ(app.get_option("--reuse-angle")->get_default_str(), "15");
    EXPECT_NE(app.help().find("axes|view"), std::string::npos) << app.help();
}

TEST(RenderFlags, RenderOffersAutoStacksByDefaultAndViewDoesNot) {
    ShearWarpSettings settings;
    bool automatic = false;
    CLI::App app;
    addStackFlags(app, settings, &automatic);
    test::parseFlags(app, {});
    EXPECT_TRUE(automatic);
    EXPECT_EQ(app.get_option("--stacks")->get_default_str(), "auto");
    EXPECT_NE(app.help().find("auto|axes|view"), std::string::npos) << app.help();

    CLI::App chosen;
    addStackFlags(chosen, settings, &automatic);
    test::parseFlags(chosen, {"--stacks", "view"});
    EXPECT_FALSE(automatic);
    EXPECT_EQ(settings.stacks, StackOrientation::View);

    CLI::App withoutAuto;
    addStackFlags(withoutAuto, settings);
    EXPECT_THROW(test::parseFlags(withoutAuto, {"--stacks", "auto"}), CLI::ParseError);

    EXPECT_EQ(automaticStacks(1), StackOrientation::View);    // a still: no shear at its own view
    EXPECT_EQ(automaticStacks(120), StackOrientation::Axes);  // an orbit: stacks built once
}

TEST(RenderFlags, StacksTakesNamesOnlyNotTheEnumsNumbers) {
    for (const char* bad : {"1", "0", "diagonal"}) {
        ShearWarpSettings settings;
        CLI::App app;
        addStackFlags(app, settings);
        EXPECT_THROW(test::parseFlags(app, {"--stacks", bad}), CLI::ParseError) << bad;
        EXPECT_EQ(settings.stacks, StackOrientation::Axes) << bad;
    }
}

TEST(RenderFlags, ImageSizeIsWidthByHeight) {
    EXPECT_EQ(parseImageSize("512x384"), std::make_pair(512, 384));
    EXPECT_EQ(parseImageSize("1x1"), std::make_pair(1, 1));
    EXPECT_EQ(parseImageSize("8192x8192"), std::make_pair(kMaxImageSide, kMaxImageSide));
    EXPECT_EQ(parseImageSize("640x480 "), std::make_pair(640, 480));  // trailing blanks, as a shell may leave
}

TEST(RenderFlags, BadImageSizesAreRefusedNamingTheFlag) {
    for (const std::string bad : {"", "512", "512x", "x512", "512X384", "512*384", "0x10", "10x0", "-5x10", "8193x10",
                                  "10x8193", "512x384x2", "5e2x10", "99999999999x10"}) {
        const std::string message = test::errorMessageOf<InputError>([&] { parseImageSize(bad); });
        EXPECT_EQ(message, "--size: '" + bad + "' is not WIDTHxHEIGHT of 1 to 8192 pixels each, e.g. 512x512") << bad;
    }
}

}  // namespace
}  // namespace gvr
