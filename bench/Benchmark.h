/// @file Benchmark.h
/// @brief The batch compression benchmark as a library call: a manifest in, a
/// results folder (results.csv, results.json, report.md, plots/) out, as
/// `gvr bench` runs it.
///
/// Every step of every run is a `gvr` subcommand in its own process, so that each
/// method is timed and sized alone and a crash fails one row, not the benchmark.
#pragma once

#include "bench/BenchTable.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace gvr {

struct BenchOptions {
    std::string manifest;       ///< .json or .toml (see BenchManifest.h)
    std::string folder;         ///< the results folder; created when missing
    std::string executable;     ///< the gvr command that runs each step
    int shard = 0, shards = 1;  ///< run units shard, shard + shards, ... (0 <= shard < shards)
    unsigned jobs = 1;          ///< volumes at once; each fit then gets cores / jobs threads
    bool resume = false;        ///< carry on in a folder that holds results
    bool retryFailed = false;   ///< with resume: run the failed rows again
    /// Called after each finished run, from the thread that ran it (one at a time),
    /// with the runs finished so far and those this call had to do.
    std::function<void(const BenchRow& row, std::size_t done, std::size_t pending)> onRow;
    /// Called before any run with each warning line (a codec whose program is missing).
    std::function<void(const std::string& warning)> onWarning;
};

struct BenchSummary {
    std::string folder;  ///< absolute
    std::vector<BenchRow> rows;
    std::size_t failed = 0;
    std::size_t skipped = 0;     ///< codecs whose programs are missing
    std::size_t duplicates = 0;  ///< mergeBenchResults: rows found in more than one folder
    std::string reportOutput;    ///< what the report script printed
};

/// Runs the manifest's pending units and writes the report. The codecs the
/// manifest runs are recorded in codecs.json (commands, programs, versions), and
/// the run in run.json (the machine, its load at the start, jobs, each volume's
/// fit budget).
/// @throw InputError for a bad manifest, shard, job count or folder, or a failed report.
BenchSummary runBenchmark(const BenchOptions& options);

/// Joins the results of several folders (shards) into @a folder, keeping the first
/// row of each (volume, ratio, method), and writes the report there.
/// @throw InputError when @a folder holds results already, or a folder cannot be read.
BenchSummary mergeBenchResults(const std::vector<std::string>& folders, const std::string& folder);

/// Writes report.md and plots/ from the folder's results.json with the report
/// script that gvr carries (left beside the results as bench_report.py, so the
/// report can be redrawn without rerunning); what the script printed.
/// @throw InputError when python3 is missing or the script fails.
std::string writeBenchReport(const std::string& folder);

}  // namespace gvr
