// gvr bench MANIFEST -o RESULTS: the batch compression benchmark (gvr, its ablations,
// ZFP, OpenVDB and downsampling), with tables and plots; and --merge of shards.

#include "BenchManifest.h"
#include "BenchReportScript.h"
#include "BenchRun.h"
#include "BenchTable.h"
#include "ChildProcess.h"
#include "Commands.h"
#include "Diagnostics.h"
#include "Error.h"
#include "Report.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iomanip>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace gvr {

namespace {

namespace fs = std::filesystem;

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

/// Units grouped by volume, in manifest order: a volume's units share its ingest
/// and reference views, so one job runs them all.
std::vector<std::vector<BenchUnit>> groupByVolume(const std::vector<BenchUnit>& units) {
    std::map<std::size_t, std::vector<BenchUnit>> byVolume;
    for (const BenchUnit& unit : units) byVolume[unit.volume].push_back(unit);
    std::vector<std::vector<BenchUnit>> groups;
    for (auto& [volume, group] : byVolume) groups.push_back(std::move(group));
    return groups;
}

std::string describeRow(const BenchRow& row) {
    std::ostringstream text;
    text << row.get("volume") << (row.get("ratio").empty() ? "" : " at " + row.get("ratio") + ":1") << ", "
         << row.get("method") << ": ";
    if (row.get("status") != "ok") return text.str() + "FAILED: " + row.get("message");
    text << formatDb(row.number("psnr").value_or(NAN)) << " dB, " << std::fixed << std::setprecision(2)
         << row.number("ratio_raw").value_or(NAN) << ":1 vs raw, render " << formatDb(row.number("render_psnr").value_or(NAN))
         << " dB, compress " << std::setprecision(1) << row.number("compress_s").value_or(NAN) << " s";
    return text.str();
}

/// gvr carries the report script inside it and leaves a copy beside the results,
/// so a long run's report can be drawn at any time, or redrawn without rerunning.
std::string writeReportScript(const std::string& folder) {
    const std::string script = folder + "/bench_report.py";
    std::ofstream out(script);
    out << reinterpret_cast<const char*>(kBenchReportScript);
    if (!out.flush()) throw InputError(script, "cannot write the report script");
    return script;
}

/// Writes report.md and the plots.
void writeReport(const std::string& folder) {
    const std::string script = writeReportScript(folder);
    const std::string python = "/usr/bin/python3";
    if (!fs::exists(python)) throw InputError(python, "not found: install python3 and python3-matplotlib for the report");
    const ChildResult result = runChild({python, script, folder}, folder + "/report.log");
    diagnostics() << result.output;
    if (!result.ok()) throw InputError(folder + "/report.md", "the report script failed: " + result.lastError);
}

void printSummary(const BenchFlags& flags, const std::vector<BenchRow>& rows, const std::string& folder) {
    std::size_t failed = 0;
    for (const BenchRow& row : rows) failed += row.get("status") != "ok";
    const nlohmann::json out = {{"rows", rows.size()},
                                {"failed", failed},
                                {"results_csv", folder + "/results.csv"},
                                {"results_json", folder + "/results.json"},
                                {"report", folder + "/report.md"},
                                {"plots", folder + "/plots"}};
    if (flags.json) {
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << rows.size() << " rows (" << failed << " failed)\n"
              << "  results: " << folder << "/results.csv and results.json\n"
              << "  report:  " << folder << "/report.md\n"
              << "  plots:   " << folder << "/plots/\n";
}

void runBench(const BenchFlags& flags) {
    const BenchManifest manifest = readBenchManifest(flags.manifest);
    const auto [shard, shards] = parseShard(flags.shard);
    if (flags.jobs < 1) throw InputError("--jobs", "must be at least 1");
    const std::string folder = fs::absolute(flags.output).lexically_normal().string();
    if (flags.retryFailed && !flags.resume) throw InputError("--retry-failed", "applies with --resume only");
    ResultsTable table(folder, fs::absolute(flags.manifest).string(), flags.resume, flags.retryFailed);
    const std::vector<std::vector<BenchUnit>> groups = groupByVolume(benchUnits(manifest, shard, shards));
    writeReportScript(folder);

    std::size_t pending = 0;
    for (const auto& group : groups) {
        for (const BenchUnit& unit : group) {
            for (const std::string& method : unit.methods) {
                pending += !table.find(benchRowKey(manifest.volumes[unit.volume].name, ratioText(unit.ratio), method));
            }
        }
    }
    std::atomic<std::size_t> done{0};
    std::mutex printing;
    BenchContext context;
    context.manifest = &manifest;
    context.folder = folder;
    context.executable = currentExecutable();
    context.table = &table;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    context.fitThreads = flags.jobs > 1 ? int(std::max(1u, cores / flags.jobs)) : 0;
    context.onRow = [&](const BenchRow& row) {
        const std::size_t n = ++done;
        if (flags.quiet) return;
        std::lock_guard<std::mutex> lock(printing);
        diagnostics() << "[" << n << "/" << pending << "] " << describeRow(row) << std::endl;
    };

    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
        for (std::size_t g = next++; g < groups.size(); g = next++) runVolumeUnits(context, groups[g]);
    };
    std::vector<std::thread> threads;
    for (unsigned j = 1; j < std::min<std::size_t>(flags.jobs, groups.size()); ++j) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();

    writeReport(folder);
    printSummary(flags, table.rows(), folder);
}

/// Joins the results of several folders (shards) into one, keeping the first row
/// of each (volume, ratio, method); file references are rewritten to stay valid.
void mergeResults(const BenchFlags& flags) {
    const fs::path out = fs::absolute(flags.output).lexically_normal();
    if (fs::exists(out / "results.csv")) throw InputError(out.string(), "already holds results; merge into a new folder");
    std::vector<BenchRow> merged;
    std::set<std::string> keys;
    std::string manifest;
    std::size_t duplicates = 0;
    for (const std::string& dir : flags.merge) {
        const fs::path from = fs::absolute(dir).lexically_normal();
        if (manifest.empty()) {
            std::ifstream in(from / "results.json");
            const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
            if (!document.is_discarded() && document.contains("manifest")) manifest = document["manifest"];
        }
        for (BenchRow row : readResultsCsv((from / "results.csv").string())) {
            if (!keys.insert(row.key()).second) {
                ++duplicates;
                continue;
            }
            const auto moved = [&](const std::string& p) { return (from / p).lexically_relative(out).string(); };
            if (!row.get("fit_log").empty()) row.set("fit_log", moved(row.get("fit_log")));
            for (const char* column : {"views", "truth_views"}) {
                std::vector<std::string> paths;
                for (const std::string& p : row.list(column)) paths.push_back(moved(p));
                row.setList(column, paths);
            }
            merged.push_back(row);
        }
    }
    fs::create_directories(out);
    writeResultsCsv((out / "results.csv").string(), merged);
    writeResultsJson((out / "results.json").string(), manifest, merged);
    if (duplicates > 0 && !flags.quiet) {
        diagnostics() << "gvr bench: " << duplicates << " rows were in more than one folder; kept the first of each\n";
    }
    writeReport(out.string());
    printSummary(flags, merged, out.string());
}

}  // namespace

void addBenchCommand(CLI::App& app) {
    auto flags = std::make_shared<BenchFlags>();
    CLI::App* command = app.add_subcommand(
        "bench",
        "Batch compression benchmark: run a manifest of volumes x target ratios x methods (gvr, ablations A1-A5, "
        "ZFP fixed-accuracy and fixed-rate, OpenVDB Blosc and half, downsampling x2/3/4), record each run in "
        "results.csv/json as it ends, and write report.md with paper-style tables and PNG plots");
    command->add_option("manifest", flags->manifest, "Manifest (.json or .toml) listing volumes, ratios, methods, "
                                                     "fit budgets and views");
    command->add_option("-o,--output", flags->output, "Results folder")->required();
    command->add_flag("--resume", flags->resume, "Carry on in a results folder, skipping the runs it already has");
    command->add_flag("--retry-failed", flags->retryFailed, "With --resume: run the failed rows again too");
    command->add_option("--shard", flags->shard,
                        "I/N: run only units I, I+N, I+2N, ... of the manifest (0 <= I < N), e.g. one per machine "
                        "or job-array task; join the folders afterwards with --merge")->capture_default_str();
    command->add_option("--jobs", flags->jobs,
                        "Volumes to run at once on this machine; each fit then gets cores/J threads, so times are "
                        "not comparable with a --jobs 1 run")->capture_default_str();
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
