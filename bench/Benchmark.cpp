#include "bench/Benchmark.h"

#include "BenchReportScript.h"
#include "bench/BenchManifest.h"
#include "bench/BenchRun.h"
#include "bench/ChildProcess.h"
#include "bench/ExternalCodec.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace gvr {

namespace {

namespace fs = std::filesystem;

/// Units grouped by volume, in manifest order: a volume's units share its ingest
/// and reference views, so one job runs them all.
std::vector<std::vector<BenchUnit>> groupByVolume(const std::vector<BenchUnit>& units) {
    std::map<std::size_t, std::vector<BenchUnit>> byVolume;
    for (const BenchUnit& unit : units) byVolume[unit.volume].push_back(unit);
    std::vector<std::vector<BenchUnit>> groups;
    for (auto& [volume, group] : byVolume) groups.push_back(std::move(group));
    return groups;
}

std::size_t pendingRuns(const BenchManifest& manifest, const std::vector<std::vector<BenchUnit>>& groups,
                        const ResultsTable& table) {
    std::size_t pending = 0;
    for (const auto& group : groups) {
        for (const BenchUnit& unit : group) {
            for (const std::string& method : unit.methods) {
                pending += !table.find(benchRowKey(manifest.volumes[unit.volume].name, ratioText(unit.ratio), method));
            }
        }
    }
    return pending;
}

void checkOptions(const BenchOptions& options) {
    if (options.shards < 1 || options.shard < 0 || options.shard >= options.shards) {
        throw InputError("shard", std::to_string(options.shard) + "/" + std::to_string(options.shards) +
                                      " is not I/N with 0 <= I < N");
    }
    if (options.jobs < 1) throw InputError("jobs", "must be at least 1");
    if (options.retryFailed && !options.resume) throw InputError("retry failed", "applies with resume only");
    if (options.executable.empty() || !fs::is_regular_file(options.executable)) {
        throw InputError(options.executable.empty() ? "executable" : options.executable,
                         "the gvr command is needed to run each step of the benchmark");
    }
}

/// Runs the volumes' groups on @a jobs threads, each group on one thread.
void runGroups(const BenchContext& context, const std::vector<std::vector<BenchUnit>>& groups, unsigned jobs) {
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
        for (std::size_t g = next++; g < groups.size(); g = next++) runVolumeUnits(context, groups[g]);
    };
    std::vector<std::thread> threads;
    for (unsigned j = 1; j < std::min<std::size_t>(jobs, groups.size()); ++j) threads.emplace_back(worker);
    worker();
    for (std::thread& t : threads) t.join();
}

std::size_t failedRows(const std::vector<BenchRow>& rows) {
    return std::size_t(
        std::count_if(rows.begin(), rows.end(), [](const BenchRow& r) { return r.get("status") == "failed"; }));
}

std::size_t skippedRows(const std::vector<BenchRow>& rows) {
    return std::size_t(
        std::count_if(rows.begin(), rows.end(), [](const BenchRow& r) { return r.get("status") == "skipped"; }));
}

void writeJsonFile(const std::string& path, const nlohmann::json& document) {
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary);
        out << jsonText(document, 2) << "\n";
        if (!out.flush()) throw InputError(path, "cannot write");
    });
}

/// The first line a codec's version command prints, or why there is none.
std::string versionOf(const ExternalCodec& codec, const std::string& folder) {
    if (codec.versionCommand.empty()) return codec.version.empty() ? "not given in the manifest" : codec.version;
    std::vector<std::string> args = codec.versionCommand;
    args.front() = findProgram(args.front());
    if (args.front().empty()) return "unknown: '" + codec.versionCommand.front() + "' not found";
    const ChildResult result = runChild(args, folder + "/codecs.log", 30.0);
    std::istringstream lines(result.output);
    for (std::string line; std::getline(lines, line);) {
        if (line.find_first_not_of(" \t\r") != std::string::npos) return line;
    }
    return "unknown: the version command printed nothing";
}

/// codecs.json: what each external codec of the run is, for the report; one warning
/// per codec whose programs are missing (its rows are skipped).
void recordCodecs(const BenchManifest& manifest, const std::string& folder,
                  const std::function<void(const std::string&)>& onWarning) {
    nlohmann::json record = nlohmann::json::object();
    for (const ExternalCodec& codec : manifest.codecs) {
        if (std::find(manifest.methods.begin(), manifest.methods.end(), codec.name) == manifest.methods.end()) continue;
        nlohmann::json programs = nlohmann::json::array();
        for (const auto* args : {&codec.compress, &codec.decompress}) {
            const std::string program = findProgram(args->front());
            programs.push_back(program.empty() ? nlohmann::json(nullptr) : nlohmann::json(program));
            if (program.empty() && onWarning) {
                onWarning("codec " + codec.name + ": program '" + args->front() + "' not found" +
                          (args->front().find('/') == std::string::npos ? " on PATH" : "") + "; its rows are skipped");
            }
        }
        record[codec.name] = {{"compress", codec.compress},
                              {"decompress", codec.decompress},
                              {"param", {codec.paramMin, codec.paramMax}},
                              {"timeout_s", codec.timeoutSeconds},
                              {"programs", programs},
                              {"version", versionOf(codec, folder)}};
    }
    writeJsonFile(folder + "/codecs.json", record);
}

/// The processor's model as /proc/cpuinfo names it, or "unknown".
std::string processorModel() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
            return line.substr(line.find_first_not_of(" \t", line.find(':') + 1));
        }
    }
    return "unknown";
}

/// run.json: what a report needs to read its times (the machine, its load, the jobs)
/// and its fits (each volume's budget). A merge keeps each shard's.
void recordRun(const BenchManifest& manifest, const BenchOptions& options, const std::string& folder) {
    double load[1] = {0.0};
    nlohmann::json budgets = nlohmann::json::object();
    for (const BenchVolume& volume : manifest.volumes) {
        budgets[volume.name] = {
            {"seconds", volume.fit.iterations ? nlohmann::json(nullptr) : nlohmann::json(volume.fit.seconds)},
            {"iterations", volume.fit.iterations ? nlohmann::json(*volume.fit.iterations) : nlohmann::json(nullptr)},
            {"args", volume.fit.args}};
    }
    const nlohmann::json run = {
        {"machine",
         {{"cpu", processorModel()},
          {"cores", std::thread::hardware_concurrency()},
          {"load_average_1min", getloadavg(load, 1) == 1 ? nlohmann::json(load[0]) : nlohmann::json(nullptr)}}},
        {"jobs", options.jobs},
        {"shard", std::to_string(options.shard) + "/" + std::to_string(options.shards)},
        {"fit", budgets}};
    writeJsonFile(folder + "/run.json", {{"runs", nlohmann::json::array({run})}});
}

/// The runs recorded in @a folders, in order.
nlohmann::json mergedRuns(const std::vector<std::string>& folders) {
    nlohmann::json runs = nlohmann::json::array();
    for (const std::string& dir : folders) {
        std::ifstream in(fs::path(dir) / "run.json");
        const nlohmann::json record = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
        if (record.is_discarded() || !record.is_object() || !record.contains("runs") || !record["runs"].is_array())
            continue;
        for (const nlohmann::json& run : record["runs"]) runs.push_back(run);
    }
    return {{"runs", runs}};
}

/// The codecs recorded in @a folders, the first record of each name kept.
nlohmann::json mergedCodecs(const std::vector<std::string>& folders) {
    nlohmann::json merged = nlohmann::json::object();
    for (const std::string& dir : folders) {
        std::ifstream in(fs::path(dir) / "codecs.json");
        const nlohmann::json record = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
        if (record.is_discarded() || !record.is_object()) continue;
        for (const auto& [name, codec] : record.items()) {
            if (!merged.contains(name)) merged[name] = codec;
        }
    }
    return merged;
}

/// @a row with its file references made relative to @a to instead of @a from.
BenchRow movedRow(BenchRow row, const fs::path& from, const fs::path& to) {
    const auto moved = [&](const std::string& p) { return (from / p).lexically_relative(to).string(); };
    if (!row.get("fit_log").empty()) row.set("fit_log", moved(row.get("fit_log")));
    for (const char* column : {"views", "truth_views"}) {
        std::vector<std::string> paths;
        for (const std::string& p : row.list(column)) paths.push_back(moved(p));
        row.setList(column, paths);
    }
    return row;
}

/// gvr carries the report script inside it and leaves a copy beside the results at
/// the start, so that a long run's report can be drawn at any time.
std::string writeReportScript(const std::string& folder) {
    const std::string script = folder + "/bench_report.py";
    writeAtomically(script, [&](const std::string& temporary) {
        std::ofstream out(temporary);
        out << reinterpret_cast<const char*>(kBenchReportScript);
        if (!out.flush()) throw InputError(script, "cannot write the report script");
    });
    return script;
}

/// gvr's own methods and the codecs the manifest declares: a resumed row of any other
/// did not come from this manifest.
std::vector<std::string> knownMethods(const BenchManifest& manifest) {
    std::vector<std::string> known = benchMethods();
    for (const ExternalCodec& codec : manifest.codecs) known.push_back(codec.name);
    return known;
}

/// Shards of two manifests would make one report of two benchmarks.
void checkOneManifest(const std::vector<std::string>& folders) {
    ManifestRecord first;
    std::string firstFolder;
    for (const std::string& folder : folders) {
        const ManifestRecord record = recordedManifest((fs::path(folder) / "results.json").string());
        if (record.digest.empty()) continue;  // written before digests were recorded
        if (first.digest.empty()) {
            first = record;
            firstFolder = folder;
        } else if (record.digest != first.digest) {
            throw InputError(folder, "holds the results of another manifest (" + record.path + ") than " + firstFolder +
                                         " (" + first.path + "); merge the shards of one manifest");
        }
    }
}

}  // namespace

std::string writeBenchReport(const std::string& folder) {
    const std::string script = writeReportScript(folder);
    const std::string python = "/usr/bin/python3";
    if (!fs::exists(python))
        throw InputError(python, "not found: install python3 and python3-matplotlib for the report");
    const ChildResult result = runChild({python, script, folder}, folder + "/report.log");
    if (!result.ok()) throw InputError(folder + "/report.md", "the report script failed: " + result.lastError);
    return result.output;
}

BenchSummary runBenchmark(const BenchOptions& options) {
    checkOptions(options);
    const BenchManifest manifest = readBenchManifest(options.manifest);
    BenchSummary summary;
    summary.folder = fs::absolute(options.folder).lexically_normal().string();
    ResultsTable table(summary.folder, fs::absolute(options.manifest).string(), options.resume, options.retryFailed,
                       knownMethods(manifest));
    const std::vector<std::vector<BenchUnit>> groups =
        groupByVolume(benchUnits(manifest, options.shard, options.shards));
    writeReportScript(summary.folder);
    recordCodecs(manifest, summary.folder, options.onWarning);
    recordRun(manifest, options, summary.folder);

    const std::size_t pending = pendingRuns(manifest, groups, table);
    std::atomic<std::size_t> done{0};
    std::mutex reporting;
    BenchContext context;
    context.manifest = &manifest;
    context.folder = summary.folder;
    context.executable = options.executable;
    context.table = &table;
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    context.fitThreads = options.jobs > 1 ? int(std::max(1u, cores / options.jobs)) : 0;
    context.onRow = [&](const BenchRow& row) {
        const std::size_t finished = ++done;
        if (!options.onRow) return;
        std::lock_guard<std::mutex> lock(reporting);
        options.onRow(row, finished, pending);
    };
    runGroups(context, groups, options.jobs);

    summary.reportOutput = writeBenchReport(summary.folder);
    summary.rows = table.rows();
    summary.failed = failedRows(summary.rows);
    summary.skipped = skippedRows(summary.rows);
    return summary;
}

BenchSummary mergeBenchResults(const std::vector<std::string>& folders, const std::string& folder) {
    const fs::path out = fs::absolute(folder).lexically_normal();
    if (fs::exists(out / "results.csv"))
        throw InputError(out.string(), "already holds results; merge into a new folder");
    BenchSummary summary;
    summary.folder = out.string();
    checkOneManifest(folders);
    std::set<std::string> keys;
    ManifestRecord manifest;
    for (const std::string& dir : folders) {
        const fs::path from = fs::absolute(dir).lexically_normal();
        if (manifest.path.empty()) manifest = recordedManifest((from / "results.json").string());
        for (const BenchRow& row : readResultsCsv((from / "results.csv").string())) {
            if (!keys.insert(row.key()).second) {
                ++summary.duplicates;
                continue;
            }
            summary.rows.push_back(movedRow(row, from, out));
        }
    }
    fs::create_directories(out);
    writeResultsCsv((out / "results.csv").string(), summary.rows);
    writeResultsJson((out / "results.json").string(), manifest, summary.rows);
    writeJsonFile((out / "codecs.json").string(), mergedCodecs(folders));
    writeJsonFile((out / "run.json").string(), mergedRuns(folders));
    summary.reportOutput = writeBenchReport(summary.folder);
    summary.failed = failedRows(summary.rows);
    summary.skipped = skippedRows(summary.rows);
    return summary;
}

}  // namespace gvr
