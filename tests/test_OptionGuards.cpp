// The guards every command's options get: no negative value for an unsigned option
// (which strtoull would wrap to 2^64 - 1), in subcommands too, and usage errors as
// one line.

#include "cli/OptionGuards.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <sstream>
#include <string>

namespace gvr {
namespace {

struct Guarded {
    CLI::App app;
    std::size_t count = 0;
    std::size_t nested = 0;
    int offset = 0;

    Guarded() {
        CLI::App* fit = app.add_subcommand("fit");
        fit->add_option("--count", count);
        fit->add_option("--offset", offset);
        fit->add_subcommand("deeper")->add_option("--nested", nested);
        refuseNegativeUnsignedValues(app);
    }

    /// The error message of parsing @a arguments (after "gvr"), or "" when it parses.
    std::string refusal(std::vector<std::string> arguments) {
        std::vector<const char*> argv{"gvr"};
        for (const std::string& argument : arguments) argv.push_back(argument.c_str());
        try {
            app.parse(int(argv.size()), argv.data());
        } catch (const CLI::ParseError& error) {
            return error.what();
        }
        return "";
    }
};

TEST(OptionGuards, NegativeValuesOfUnsignedOptionsAreRefusedNotWrapped) {
    Guarded guarded;
    const std::string wrapped = guarded.refusal({"fit", "--count", "-1"});
    EXPECT_NE(wrapped.find("must not be negative, got -1"), std::string::npos) << wrapped;
    EXPECT_NE(Guarded().refusal({"fit", "--count", " -3"}), "") << "leading blanks do not hide the sign";
    EXPECT_NE(Guarded().refusal({"fit", "deeper", "--nested", "-2"}), "")
        << "subcommands of subcommands are guarded too";
}

TEST(OptionGuards, SignedOptionsAndPositiveCountsPass) {
    Guarded guarded;
    EXPECT_EQ(guarded.refusal({"fit", "--count", "5", "--offset", "-1"}), "");
    EXPECT_EQ(guarded.count, 5u);
    EXPECT_EQ(guarded.offset, -1);
}

TEST(OptionGuards, UsageErrorsAreOneLineNamedAsGvrErrors) {
    CLI::App app;
    useOneLineUsageErrors(app);
    std::ostringstream out, err;
    const int code = app.exit(CLI::ValidationError("--count", "must not be negative"), out, err);
    EXPECT_NE(code, 0);
    EXPECT_EQ(err.str().rfind("gvr: error: ", 0), 0u) << err.str();
    EXPECT_EQ(err.str().find('\n'), err.str().size() - 1) << "one line: " << err.str();
    EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace gvr
