#include "cli/Commands.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

namespace gvr {
namespace {

/// The subcommands addCommands() gives an application of its own.
std::vector<const CLI::App*> commandsOf(const CLI::App& app) {
    return app.get_subcommands([](const CLI::App*) { return true; });
}

std::vector<std::string> namesOf(const std::vector<const CLI::App*>& commands) {
    std::vector<std::string> names;
    for (const CLI::App* command : commands) names.push_back(command->get_name());
    return names;
}

TEST(Commands, AddsEveryCommandOnceInTheOrderOfASession) {
    CLI::App app;
    addCommands(app);
    EXPECT_EQ(namesOf(commandsOf(app)), (std::vector<std::string>{"ingest", "info", "fit", "merge", "export", "eval",
                                                                  "probe", "render", "view", "baseline", "bench"}));
}

TEST(Commands, EveryCommandAndOptionExplainsItself) {
    CLI::App app;
    addCommands(app);
    for (const CLI::App* command : commandsOf(app)) {
        EXPECT_FALSE(command->get_description().empty()) << command->get_name();
        for (const CLI::Option* option : command->get_options()) {
            if (option->get_group().empty()) continue;  // hidden: a removed flag kept to say so
            EXPECT_FALSE(option->get_description().empty())
                << command->get_name() << " " << option->get_name(false, true);
        }
    }
}

TEST(Commands, EveryCommandAnswersInJson) {
    CLI::App app;
    addCommands(app);
    for (const CLI::App* command : commandsOf(app)) {
        EXPECT_NE(command->get_option_no_throw("--json"), nullptr) << command->get_name();
    }
}

TEST(Commands, CommandsThatDrawProgressBarsCanBeQuiet) {
    CLI::App app;
    addCommands(app);
    const std::set<std::string> withBars = {"ingest", "fit", "export", "render", "baseline", "bench"};
    for (const CLI::App* command : commandsOf(app)) {
        if (withBars.count(command->get_name()) == 0) continue;
        EXPECT_NE(command->get_option_no_throw("--quiet"), nullptr) << command->get_name();
    }
}

TEST(Commands, HelpOfEachCommandStopsBeforeItRuns) {
    for (const std::string name : {"ingest", "fit", "export", "render", "view", "bench"}) {
        CLI::App app;
        addCommands(app);
        std::vector<std::string> args = {"--help", name};  // CLI11 takes them last first
        EXPECT_THROW(app.parse(args), CLI::CallForHelp) << name;
    }
}

}  // namespace
}  // namespace gvr
