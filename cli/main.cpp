// gvr: medical volumes to compact Gaussian assets, and back.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/OptionGuards.h"
#include "cli/Suggestions.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"

#include <filesystem>
#include <iostream>
#include <memory>
#include <new>

namespace {

int run(CLI::App& app, int argc, char** argv) {
    const std::string unknownCommand = gvr::unknownCommandMessage(app, argc, argv);
    if (!unknownCommand.empty()) {
        gvr::diagnostics() << "gvr: error: " << unknownCommand << "\n";
        return 2;
    }
    try {
        app.parse(argc, argv);
        return 0;
    } catch (const CLI::ExtrasError& error) {
        const std::string unknownFlag = gvr::unknownFlagMessage(app, argc, argv);
        if (unknownFlag.empty()) return app.exit(error, std::cout, gvr::diagnostics()) == 0 ? 0 : 2;
        gvr::diagnostics() << "gvr: error: " << unknownFlag << "\n";
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error, std::cout, gvr::diagnostics());
        return code == 0 ? 0 : 2;
    } catch (const gvr::InputError& error) {
        gvr::diagnostics() << "gvr: error: " << gvr::inCommandLineTerms(error.what()) << "\n";
    } catch (const std::filesystem::filesystem_error& error) {
        gvr::diagnostics() << "gvr: error: " << error.what() << "\n";
    } catch (const std::bad_alloc&) {
        gvr::diagnostics() << "gvr: error: out of memory\n";
    } catch (const std::exception& error) {
        gvr::diagnostics() << "gvr: internal error: " << error.what() << "\n";
        return 1;
    }
    return 2;
}

/// gvr help [COMMAND]: the help that --help prints.
void addHelpCommand(CLI::App& app) {
    auto topic = std::make_shared<std::string>();
    CLI::App* help = app.add_subcommand("help", "Show the help of gvr, or of one command (gvr help fit)");
    help->add_option("command", *topic, "The command to explain");
    help->callback([&app, topic] {
        if (topic->empty()) {  // app.help() would explain the help command itself, the one selected
            std::cout << app.get_formatter()->make_help(&app, "gvr", CLI::AppFormatMode::Normal);
            return;
        }
        std::vector<std::string> names;
        for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
            if (command->get_name() == *topic) {
                std::cout << command->help(app.get_name());
                return;
            }
            names.push_back(command->get_name());
        }
        const std::string near = gvr::closestName(*topic, names);
        throw gvr::InputError("help",
                              "no command '" + *topic + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?"));
    });
}

}  // namespace

int main(int argc, char** argv) {
    gvr::divertLibraryOutput();
    gvr::removeTemporariesOnSignals();
    CLI::App app{
        "gvr: turn medical volumes into sparse OpenVDB grids and compact Gaussian assets, "
        "evaluate and render them"};
    app.name("gvr");  // not argv[0], a build path, in every usage line
    app.require_subcommand(1);
    app.set_version_flag("-V,--version", "gvr " GVR_VERSION);
    app.fallthrough();  // inherited by the subcommands, so that --verbose may follow them
    gvr::addCommands(app);
    addHelpCommand(app);
    gvr::refuseNegativeUnsignedValues(app);
    gvr::useOneLineUsageErrors(app);
    bool verbose = false;
    app.add_flag("--verbose", verbose,
                 "Also print what the libraries (libpng, nifticlib, GDCM) wrote, after gvr's own output");
    const int code = run(app, argc, argv);
    if (verbose) gvr::showLibraryOutput();
    return code;
}
