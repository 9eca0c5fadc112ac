// "Did you mean ...?": the nearest name by edits or by a unique prefix, and the
// messages for a mistyped command or flag.

#include "cli/Suggestions.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace gvr {
namespace {

const std::vector<std::string> kCommands = {"fit", "info", "export", "eval", "render"};

TEST(Suggestions, NearestNameByEditsOrByAUniquePrefix) {
    EXPECT_EQ(closestName("fti", kCommands), "fit");       // two edits
    EXPECT_EQ(closestName("rendr", kCommands), "render");  // one edit
    EXPECT_EQ(closestName("exp", kCommands), "export");    // three edits from both, but the only name it begins
    EXPECT_EQ(closestName("zzzzzzzz", kCommands), "");
    EXPECT_EQ(closestName("ren", {"render-one", "render-two"}), "");  // a prefix of two names: no guess
    EXPECT_EQ(closestName("--tim", {"--time", "--tf", "--threads"}), "--time");
    EXPECT_EQ(closestName("--iter", {"--iterations", "--time"}), "--iterations");  // the only one it begins
}

TEST(Suggestions, UnknownCommandNamesTheArgumentAndTheNearestCommand) {
    CLI::App app;
    for (const std::string& name : kCommands) app.add_subcommand(name);
    const char* mistyped[] = {"gvr", "--verbose", "fitt", "a.vdb"};
    const std::string message = unknownCommandMessage(app, 4, mistyped);
    EXPECT_NE(message.find("unknown command 'fitt'"), std::string::npos) << message;
    EXPECT_NE(message.find("did you mean 'fit'?"), std::string::npos) << message;
    const char* right[] = {"gvr", "--verbose", "fit", "a.vdb"};
    EXPECT_EQ(unknownCommandMessage(app, 4, right), "");
}

TEST(Suggestions, UnknownFlagNamesTheCommandAndTheNearestOption) {
    CLI::App app;
    CLI::App* fit = app.add_subcommand("fit");
    double time = 0.0, offset = 0.0;
    fit->add_option("--time", time);
    fit->add_option("--offset", offset);
    const char* parsed[] = {"gvr", "fit"};
    app.parse(2, parsed);  // the message reads which command was parsed, then the arguments
    const char* argv[] = {"gvr", "fit", "--offset", "-5", "--tme=5"};
    const std::string message = unknownFlagMessage(app, 5, argv);
    // "-5" is a negative number, not a flag; "--tme=5" names "--tme".
    EXPECT_NE(message.find("fit: unknown option --tme;"), std::string::npos) << message;
    EXPECT_NE(message.find("did you mean --time?"), std::string::npos) << message;

    const char* known[] = {"gvr", "fit", "--time", "5", "--offset=-2"};
    EXPECT_EQ(unknownFlagMessage(app, 5, known), "");
}

}  // namespace
}  // namespace gvr
