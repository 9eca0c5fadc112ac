// gvr baseline INPUT --method M -o RECON.vdb --stream FILE: the reference codecs
// that gvr's Gaussians are measured against, with the reconstruction they give.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/GridSummary.h"
#include "cli/ProgressBar.h"
#include "cli/SourceOptions.h"
#include "io/formats/GridFile.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "workflow/BaselineCodecs.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct BaselineFlags {
    std::string input, method, output, stream;
    BaselineSettings settings;
    bool json = false, quiet = false;
    SourceFlags source;
};

nlohmann::json toJson(const BaselineFlags& flags, const BaselineResult& r) {
    nlohmann::json out = {{"method", flags.method},
                          {"stream", flags.stream},
                          {"output", flags.output},
                          {"bytes", r.streamBytes},
                          {"bits_per_voxel", r.bitsPerValue()},
                          {"compress_s", r.compressSeconds},
                          {"decompress_s", r.decompressSeconds},
                          {"voxels", r.voxels},
                          {"channels", r.channels}};
    if (r.tolerance) out["tolerance"] = *r.tolerance;
    if (r.rate) out["rate"] = *r.rate;
    if (r.factor) out["factor"] = *r.factor;
    if (r.matched) out["matched"] = *r.matched;
    return out;
}

/// "tolerance 0.25 (target 12000 bytes: matched)", "rate 4 bits per value", "factor 2",
/// or nothing for the vdb methods.
std::string parameterText(const BaselineFlags& flags, const BaselineResult& r) {
    std::ostringstream text;
    if (r.tolerance) text << "tolerance " << *r.tolerance;
    if (r.matched) {
        text << " (target " << *flags.settings.targetBytes << " bytes: " << (*r.matched ? "matched" : "not reached")
             << ")";
    }
    if (r.rate) text << "rate " << *r.rate << " bits per value";
    if (r.factor) text << "factor " << *r.factor;
    return text.str();
}

void printResult(const BaselineFlags& flags, const BaselineResult& r) {
    if (flags.json) {
        std::cout << jsonText(toJson(flags, r), 2) << "\n";
        return;
    }
    const std::string parameter = parameterText(flags, r);
    std::cout << "wrote " << flags.stream << " (" << formatBytes(r.streamBytes) << ", " << r.bitsPerValue()
              << " bits per value) and " << flags.output << ": " << flags.method
              << (parameter.empty() ? "" : ", " + parameter) << "\n"
              << "compress " << r.compressSeconds << " s, decompress " << r.decompressSeconds << " s; " << r.voxels
              << " voxels x " << r.channels << " channel(s)\n";
}

void runBaselineCommand(BaselineFlags& flags) {
    flags.settings.method = parseBaselineMethod(flags.method);
    if (const std::string problem = flags.settings.validate(); !problem.empty()) {
        throw InputError("gvr baseline", problem);
    }
    checkOutputPath("-o", flags.output, {flags.input});
    checkOutputPath("--stream", flags.stream, {flags.input, flags.output});
    namespace fs = std::filesystem;
    if (fs::weakly_canonical(flags.stream) == fs::weakly_canonical(flags.output)) {
        throw InputError("--stream", "must be another file than -o " + flags.output);
    }
    const IngestResult source = loadOrIngest(flags.input, toIngestOptions(flags.source));
    for (const std::string& warning : source.warnings)
        diagnostics() << "gvr: warning: " << inCommandLineTerms(warning) << "\n";
    BaselineResult result;
    {
        ProgressBar bar(flags.method, !flags.quiet);
        result = runBaseline(*source.grid, flags.settings, flags.stream, bar.callback());
    }
    try {
        writeGridFile(flags.output, {result.reconstruction});
    } catch (...) {
        std::error_code ignored;
        fs::remove(flags.stream, ignored);
        throw;
    }
    printResult(flags, result);
}

}  // namespace

void addBaselineCommand(CLI::App& app) {
    auto flags = std::make_shared<BaselineFlags>();
    CLI::App* command =
        app.add_subcommand("baseline",
                           "Compress a volume with a reference codec (zfp, OpenVDB Blosc or half, downsampling), "
                           "then write what decodes from it as a grid on the source's lattice, for eval and render");
    command->add_option("input", flags->input, ".vdb grid, or any volume ingest reads")->required();
    command->add_option("--method", flags->method, "zfp-accuracy, zfp-rate, vdb-blosc, vdb-half or downsample")
        ->required();
    command->add_option("-o,--output", flags->output, "Reconstruction to write (.vdb)")->required();
    command
        ->add_option("--stream", flags->stream,
                     "Compressed stream to write: a zfp stream, or a .vdb for vdb-* and downsample")
        ->required();
    command->add_option("--tolerance", flags->settings.tolerance,
                        "zfp-accuracy: largest absolute error, physical units");
    command->add_option("--target-bytes", flags->settings.targetBytes,
                        "zfp-accuracy: search the tolerance for a stream within 5% of this size");
    command->add_option("--rate", flags->settings.rate, "zfp-rate: compressed bits per value of one channel");
    command->add_option("--factor", flags->settings.factor,
                        "downsample: average FxFxF boxes, reconstruct by trilinear upsampling");
    addSourceFlags(*command, flags->source);
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bar");
    command->callback([flags] { runBaselineCommand(*flags); });
}

}  // namespace gvr
