// gvr bench MANIFEST -o RESULTS: the batch compression benchmark (gvr, its ablations,
// ZFP, OpenVDB and downsampling), with tables and plots; and --merge of shards.

#include "bench/Benchmark.h"
#include "bench/ChildProcess.h"
#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "workflow/ReportNumbers.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <tuple>

namespace gvr {

namespace {

struct BenchFlags {
    std::string manifest, output, shard = "0/1";
    std::vector<std::string> merge;
    unsigned jobs = 1;
    bool resume = false, retryFailed = false, json = false, quiet = false;
};

std::pair<int, int> parseShard(const std::string& text) {
    int index = -1, count = 0;
    char slash = 0;
    std::istringstream in(text);
    if (!(in >> index >> slash >> count) || slash != '/' || !(in >> std::ws).eof() || count < 1 || index < 0 ||
        index >= count) {
        throw InputError("--shard", "'" + text + "' is not I/N with 0 <= I < N, e.g. 0/4 ... 3/4");
    }
    return {index, count};
}

std::string describeRow(const BenchRow& row) {
    std::ostringstream text;
    // By the ratio reached, with the target beside it: the two can differ several times over.
    text << row.get("volume") << ", " << row.get("method")
         << (row.get("ratio").empty() ? "" : " (target " + row.get("ratio") + ":1)") << ": ";
    if (row.get("status") == "skipped") return text.str() + "skipped: " + row.get("message");
    if (row.get("status") != "ok") return text.str() + "FAILED: " + row.get("message");
    text << formatDb(row.number("psnr").value_or(NAN)) << " dB at " << std::fixed << std::setprecision(2)
         << row.number("ratio_raw").value_or(NAN) << ":1 vs raw, render "
         << formatDb(row.number("render_psnr").value_or(NAN)) << " dB, compress " << std::setprecision(1)
         << row.number("compress_s").value_or(NAN) << " s";
    return text.str();
}

void printSummary(const BenchFlags& flags, const BenchSummary& summary) {
    const std::string& folder = summary.folder;
    const nlohmann::json out = {{"rows", summary.rows.size()},
                                {"failed", summary.failed},
                                {"skipped", summary.skipped},
                                {"results_csv", folder + "/results.csv"},
                                {"results_json", folder + "/results.json"},
                                {"report", folder + "/report.md"},
                                {"plots", folder + "/plots"}};
    if (flags.json) {
        std::cout << jsonText(out, 2) << "\n";
        return;
    }
    std::cout << summary.rows.size() << " rows (" << summary.failed << " failed, " << summary.skipped << " skipped)\n"
              << "  results: " << folder << "/results.csv and results.json\n"
              << "  report:  " << folder << "/report.md\n"
              << "  plots:   " << folder << "/plots/\n";
}

void runBench(const BenchFlags& flags) {
    BenchOptions options;
    options.manifest = flags.manifest;
    options.folder = flags.output;
    options.executable = currentExecutable();
    std::tie(options.shard, options.shards) = parseShard(flags.shard);
    options.jobs = flags.jobs;
    options.resume = flags.resume;
    options.retryFailed = flags.retryFailed;
    options.onWarning = [](const std::string& warning) { diagnostics() << "gvr: warning: " << warning << std::endl; };
    if (!flags.quiet) {
        options.onRow = [](const BenchRow& row, std::size_t done, std::size_t pending) {
            diagnostics() << "[" << done << "/" << pending << "] " << describeRow(row) << std::endl;
        };
    }
    // A long run is often stopped by hand: the line says that nothing is lost.
    const SaidOnSignal howToCarryOn("gvr bench: stopped; the runs that ended are kept in " + flags.output +
                                        "/results.csv; carry on with: gvr bench " + flags.manifest + " -o " +
                                        flags.output + " --resume",
                                    diagnosticsFd());
    const BenchSummary summary = runBenchmark(options);
    diagnostics() << summary.reportOutput;
    printSummary(flags, summary);
}

void mergeResults(const BenchFlags& flags) {
    const BenchSummary summary = mergeBenchResults(flags.merge, flags.output);
    if (summary.duplicates > 0 && !flags.quiet) {
        diagnostics() << "gvr bench: " << summary.duplicates
                      << " rows were in more than one folder; kept the first of each\n";
    }
    diagnostics() << summary.reportOutput;
    printSummary(flags, summary);
}

}  // namespace

void addBenchCommand(CLI::App& app) {
    auto flags = std::make_shared<BenchFlags>();
    CLI::App* command = app.add_subcommand(
        "bench",
        "Batch compression benchmark: run a manifest of volumes x target ratios x methods (gvr, ablations A1-A5, "
        "ZFP fixed-accuracy and fixed-rate, OpenVDB Blosc and half, downsampling x2/3/4, and external codecs such "
        "as SZ3 and SPERR declared in the manifest), record each run in "
        "results.csv/json as it ends, and write report.md with paper-style tables and PNG plots");
    command->add_option("manifest", flags->manifest,
                        "Manifest (.json or .toml) listing volumes, ratios, methods, "
                        "fit budgets and views");
    command->add_option("-o,--output", flags->output, "Results folder")->required();
    CLI::Option* resume =
        command->add_flag("--resume", flags->resume, "Carry on in a results folder, skipping the runs it already has");
    command->add_flag("--retry-failed", flags->retryFailed, "With --resume: run the failed rows again too")
        ->needs(resume);
    command
        ->add_option("--shard", flags->shard,
                     "I/N: run only units I, I+N, I+2N, ... of the manifest (0 <= I < N), e.g. one per machine "
                     "or job-array task; join the folders afterwards with --merge")
        ->capture_default_str();
    command
        ->add_option("--jobs", flags->jobs,
                     "Volumes to run at once on this machine; each fit then gets cores/J threads, so times are "
                     "not comparable with a --jobs 1 run")
        ->capture_default_str()
        ->check(CLI::Range(1u, 256u));
    command->add_option("--merge", flags->merge, "Join the results folders of several shards into -o, then report")
        ->expected(1, -1);
    command->add_flag("--json", flags->json, "Print the summary as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No line per finished run");
    command->callback([flags] {
        if (flags->merge.empty() == flags->manifest.empty()) {
            throw InputError("gvr bench", "give either a MANIFEST or --merge DIR...");
        }
        if (flags->merge.empty()) {
            runBench(*flags);
        } else {
            mergeResults(*flags);
        }
    });
}

}  // namespace gvr
