/// @file BenchManifest.h
/// @brief What a batch benchmark runs: volumes, target ratios, methods, budgets
/// and views, read from a JSON or TOML manifest.
///
///     {
///       "ratios": [10, 40],
///       "methods": ["gvr", "A1", "zfp-accuracy", "vdb-half", "down2"],
///       "fit": {"seconds": 60, "args": ["--batch", "16384"]},
///       "render": {"size": "256x256", "views": 6, "elevation": 20},
///       "volumes": [
///         {"name": "ch2", "input": "../data/ch2.nii.gz"},
///         {"name": "brainmaps", "input": "../data/brainmaps", "ingest": ["--spacing", "1,1,3.5"],
///          "ratios": [10], "fit": {"seconds": 600}}
///       ]
///     }
///
/// The same keys work in TOML. Relative inputs resolve against the manifest's folder.
/// "methods" defaults to every method but gvr+bound; a volume's "ratios" and "fit" override the
/// top-level ones.
///
/// Codecs outside gvr are declared under "codecs" and then named in "methods" like
/// any other (see ExternalCodec.h for the placeholders):
///
///     "codecs": {"sz3": {
///         "compress":   ["sz3", "-f", "-i", "{input}", "-z", "{compressed}", "-3", "{nx}", "{ny}", "{nz}", "-M", "REL", "{param}"],
///         "decompress": ["sz3", "-f", "-z", "{compressed}", "-o", "{output}", "-3", "{nx}", "{ny}", "{nz}", "-M", "REL", "{param}"],
///         "param": [1e-7, 0.1], "version": ["sz3", "-v"], "timeout": 600}}
///
/// A program holding a '/' resolves against the manifest's folder, any other is
/// looked up on PATH when the run starts. "version" is a text, or a command whose
/// first line of output is recorded; "timeout" is the seconds a row may take, every
/// compression of its search and the decompression together.
#pragma once

#include "bench/ExternalCodec.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gvr {

/// Every method the benchmark knows, in report order. "gvr+bound" is gvr's fit with
/// `--max-error auto`: the smallest error bound with which the asset fits the ratio.
const std::vector<std::string>& benchMethods();

/// The methods a manifest without "methods" runs: all but gvr+bound, whose second
/// fit a ratio would double the benchmark's time.
const std::vector<std::string>& defaultBenchMethods();

/// Methods whose result does not depend on the target ratio (run once per volume).
bool isRatioFree(const std::string& method);

/// gvr fits: "gvr" (the full method), "gvr+bound" and the ablations "A1".."A5".
bool isFitMethod(const std::string& method);

struct FitBudget {
    double seconds = 60.0;
    std::optional<std::uint64_t> iterations;  ///< instead of seconds: reproducible fits
    std::vector<std::string> args;            ///< extra `gvr fit` flags
};

struct BenchVolume {
    std::string name;   ///< unique; names rows, folders and plots
    std::string input;  ///< absolute, or as given when it is not a path (a glob)
    std::vector<std::string> ingestArgs;
    std::vector<double> ratios;
    FitBudget fit;
};

struct RenderPlan {
    std::string size = "256x256";
    int views = 6;  ///< azimuths 0, 360/views, ... at one elevation
    double elevation = 20.0;
    std::string tf;  ///< preset or file; empty: the source's default preset
};

struct BenchManifest {
    std::string path;
    std::vector<BenchVolume> volumes;
    std::vector<std::string> methods;
    std::vector<ExternalCodec> codecs;  ///< declared, whether or not "methods" names them
    RenderPlan render;

    /// The declared codec named @a method, or nullptr for gvr's own methods.
    const ExternalCodec* codec(const std::string& method) const;
};

/// @throw InputError naming the manifest (and the key) for anything malformed:
///        unknown methods or keys, duplicate names, ratios <= 1, missing inputs.
BenchManifest readBenchManifest(const std::string& path);

/// One piece of work: a volume at one target ratio, or (ratio unset) the volume's
/// ratio-free methods.
struct BenchUnit {
    std::size_t volume = 0;
    std::optional<double> ratio;
    std::vector<std::string> methods;
};

/// All units in manifest order. Shard @a shard of @a shards takes every unit whose
/// index modulo @a shards is @a shard, so any split covers each unit exactly once.
std::vector<BenchUnit> benchUnits(const BenchManifest& manifest, int shard = 0, int shards = 1);

/// "10", "7.5": how a ratio appears in keys, folders and reports.
std::string ratioText(std::optional<double> ratio);

}  // namespace gvr
