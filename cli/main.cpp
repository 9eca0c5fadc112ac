// gvr: medical volumes to compact Gaussian assets, and back.

#include "AtomicFile.h"
#include "Commands.h"
#include "Diagnostics.h"
#include "Error.h"
#include "OptionGuards.h"

#include <filesystem>
#include <iostream>
#include <new>

namespace {

int run(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        return 0;
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error, std::cout, gvr::diagnostics());
        return code == 0 ? 0 : 2;
    } catch (const gvr::InputError& error) {
        gvr::diagnostics() << "gvr: error: " << error.what() << "\n";
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

}  // namespace

int main(int argc, char** argv) {
    gvr::divertLibraryOutput();
    gvr::removeTemporariesOnSignals();
    CLI::App app{"gvr: turn medical volumes into sparse OpenVDB grids and compact Gaussian assets, "
                 "evaluate and render them"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "gvr 0.1.0");
    app.fallthrough();  // inherited by the subcommands, so that --verbose may follow them
    gvr::addIngestCommand(app);
    gvr::addInfoCommand(app);
    gvr::addFitCommand(app);
    gvr::addMergeCommand(app);
    gvr::addExportCommand(app);
    gvr::addEvalCommand(app);
    gvr::addProbeCommand(app);
    gvr::addRenderCommand(app);
    gvr::addViewCommand(app);
    gvr::addBaselineCommand(app);
    gvr::addBenchCommand(app);
    gvr::refuseNegativeUnsignedValues(app);
    gvr::useOneLineUsageErrors(app);
    bool verbose = false;
    app.add_flag("--verbose", verbose, "Also print what the libraries (libpng, nifticlib, GDCM) wrote, after gvr's own output");
    const int code = run(app, argc, argv);
    if (verbose) gvr::showLibraryOutput();
    return code;
}
