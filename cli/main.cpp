// gvr: medical volumes to compact Gaussian assets, and back.

#include "Commands.h"
#include "Error.h"
#include "OptionGuards.h"

#include <filesystem>
#include <iostream>
#include <new>

int main(int argc, char** argv) {
    CLI::App app{"gvr: turn medical volumes into sparse OpenVDB grids and compact Gaussian assets, "
                 "evaluate and render them"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "gvr 0.1.0");
    gvr::addIngestCommand(app);
    gvr::addInfoCommand(app);
    gvr::addFitCommand(app);
    gvr::addExportCommand(app);
    gvr::addEvalCommand(app);
    gvr::addProbeCommand(app);
    gvr::addRenderCommand(app);
    gvr::addBaselineCommand(app);
    gvr::addBenchCommand(app);
    gvr::refuseNegativeUnsignedValues(app);
    gvr::useOneLineUsageErrors(app);
    try {
        app.parse(argc, argv);
        return 0;
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error);
        return code == 0 ? 0 : 2;
    } catch (const gvr::InputError& error) {
        std::cerr << "gvr: error: " << error.what() << "\n";
    } catch (const std::filesystem::filesystem_error& error) {
        std::cerr << "gvr: error: " << error.what() << "\n";
    } catch (const std::bad_alloc&) {
        std::cerr << "gvr: error: out of memory\n";
    } catch (const std::exception& error) {
        std::cerr << "gvr: internal error: " << error.what() << "\n";
        return 1;
    }
    return 2;
}
