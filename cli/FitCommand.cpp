// gvr fit IN -o ASSET: Gaussians fitted to a grid, with error against run time.

#include "cli/Commands.h"
#include "cli/Diagnostics.h"
#include "cli/FitLog.h"
#include "cli/GridSummary.h"
#include "cli/ProgressBar.h"
#include "cli/SourceOptions.h"
#include "io/LabelGrid.h"
#include "io/asset/AssetFile.h"
#include "io/formats/GridFile.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "pipeline/FieldAccuracy.h"
#include "pipeline/GaussianField.h"
#include "pipeline/LabelBudget.h"
#include "pipeline/ProcessMemory.h"
#include "workflow/FitJob.h"
#include "workflow/MpiTeam.h"
#include "workflow/PhaseTimes.h"
#include "workflow/ReportNumbers.h"
#include "workflow/TeamFit.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace gvr {

namespace {

/// --bricks N, or --brick I --of N.
struct BrickFlags {
    std::size_t count = 0;  ///< --bricks, or --of with --brick
    int halo = kDefaultBrickHalo;
    std::optional<std::size_t> only;  ///< --brick I: fit this one and write its part

    bool any() const { return count > 0; }
    BrickOptions options() const { return {count, halo}; }
};

struct FitFlags {
    std::string input, output, logPath, labelVolume, labelNames;
    std::string maxError;     ///< --max-error as given: empty, a number, a percentage or auto
    bool ratioGiven = false;  ///< --ratio on the command line (else a bound's preview takes kBoundedPreviewRatio)
    std::size_t threads = 0;
    bool json = false, quiet = false;
    BudgetedFitOptions options;
    SourceFlags source;
    BrickFlags bricks;
};

FitObserver progressObserver(ProgressBar& bar, FitLog& log) {
    return [&bar, &log, lastPsnr = std::string("-")](const FitProgress& p) mutable {
        if (p.setUp) {
            bar.update(p.fraction, "setting up: seeds " + std::to_string(int(100.0 * *p.setUp)) + " %");
            return;
        }
        if (p.heldOutEvaluated) lastPsnr = formatDb(p.heldOutPsnr);
        bar.update(p.fraction, "it " + std::to_string(p.iteration) + ", " + lastPsnr + " dB held-out, " +
                                   std::to_string(p.gaussians) + " Gaussians");
        log.record(p);
    };
}

FitObserver brickObserver(ProgressBar& bar, std::size_t brick) {
    return [&bar, brick](const FitProgress& p) {
        bar.update(p.fraction, "brick " + std::to_string(brick) + ", it " + std::to_string(p.iteration) + ", " +
                                   std::to_string(p.gaussians) + " Gaussians");
    };
}

/// A bar for each brick while it is fitted.
BrickObservers brickBars(bool shown) {
    return [shown](std::size_t brick) {
        auto bar = std::make_shared<ProgressBar>("fitting", shown);
        return FitObserver([bar, observe = brickObserver(*bar, brick)](const FitProgress& p) { observe(p); });
    };
}

/// The fit's bar, then from the residual layer's first report the layer's: one bar
/// drawn at a time, each timing its own step.
class FitBars {
public:
    explicit FitBars(bool shown) : mShown(shown), mFitting(std::make_unique<ProgressBar>("fitting", shown)) {}

    FitJobObservers observers(FitLog& log) {
        return {progressObserver(*mFitting, log), {}, [this](double fraction) {
                    if (!mLayer) {
                        mFitting.reset();
                        mLayer = std::make_unique<ProgressBar>("residual layer", mShown);
                    }
                    mLayer->update(fraction);
                }};
    }

private:
    bool mShown;
    std::unique_ptr<ProgressBar> mFitting, mLayer;
};

/// Rank @a rank's error, before it ends the team.
void reportTeamError(int rank, int size, const std::exception& error) {
    diagnostics() << "gvr: error (rank " << rank << " of " << size << "): " << inCommandLineTerms(error.what()) << "\n";
}

/// When the run after reading took over 2 % more than --time: one line saying so,
/// with the costs that do not shrink with the budget (a large volume's set-up and
/// final measurement can outlast a short one). Else empty.
std::string overrunNote(const PhaseTimes& phases, const FitReport& fit, double budget) {
    const nlohmann::json laps = phases.json();
    const double afterLoading = phases.total() - laps.value("load", 0.0);
    if (!(budget > 0.0) || afterLoading <= 1.02 * budget) return "";
    std::ostringstream note;
    note << std::fixed << std::setprecision(1) << "the fit took " << afterLoading << " s after reading, over --time "
         << budget << ": on this volume the set-up alone takes " << fit.setupSeconds << " s, " << fit.iterations
         << (fit.iterations == 1 ? " iteration " : " iterations ") << fit.adamSeconds - fit.setupSeconds
         << " s and the final measurement " << laps.value("measure", 0.0) << " s";
    return note.str();
}

/// The final amplitude solve, with why it did not run ("skipped") or null, and no
/// PSNRs for a solve that did not run.
nlohmann::json amplitudeSolveJson(const FitReport& fit, double peak) {
    const AmplitudeSolveReport& solve = fit.amplitudeSolve;
    const bool ran = solve.mseBefore > 0.0;
    return {
        {"skipped", fit.amplitudeSolveSkipped.empty() ? nlohmann::json() : nlohmann::json(fit.amplitudeSolveSkipped)},
        {"iterations", solve.iterations},
        {"seconds", solve.seconds},
        {"psnr_before_db", ran ? jsonNumber(psnrFromMse(solve.mseBefore, peak)) : nlohmann::json()},
        {"psnr_after_db", ran ? jsonNumber(psnrFromMse(solve.mseAfter, peak)) : nlohmann::json()}};
}

nlohmann::json structuresJson(const GaussianAsset& asset, const std::vector<StructureFit>& structures) {
    nlohmann::json out = nlohmann::json::array();
    for (const StructureFit& s : structures) {
        out.push_back({{"id", s.id},
                       {"name", asset.labelTable.nameOf(s.id)},
                       {"voxels", s.voxels},
                       {"gaussians", std::count(asset.labels.begin(), asset.labels.end(), s.id)},
                       {"budget", s.budget},
                       {"iterations", s.report.iterations},
                       {"seconds", s.report.seconds}});
    }
    return out;
}

nlohmann::json bricksJson(const std::vector<BrickReport>& bricks) {
    nlohmann::json out = nlohmann::json::array();
    for (const BrickReport& b : bricks) {
        out.push_back({{"brick", b.brick},
                       {"budget", b.budget},
                       {"rank", b.run.rank},
                       {"gaussians", b.run.gaussians},
                       {"iterations", b.run.iterations},
                       {"seconds", b.run.seconds},
                       {"rank_peak_rss_mib", b.run.rankPeakRssMiB}});
    }
    return out;
}

void reportBricks(const TeamFitResult& bricked, const FieldAccuracy& error) {
    std::cout << "  seams:           " << formatDb(error.markedPsnr) << " dB within " << kSeamWidth
              << " voxels of a face between bricks (" << error.markedVoxels << " voxels), "
              << formatDb(error.unmarkedPsnr) << " dB elsewhere; over the active voxels "
              << formatDb(error.markedForegroundPsnr) << " / " << formatDb(error.unmarkedForegroundPsnr) << " dB\n";
    for (const BrickReport& b : bricked.bricks) {
        std::cout << "  brick " << b.brick << ":" << std::setw(8) << b.run.gaussians << " Gaussians (budget "
                  << b.budget << "), rank " << b.run.rank << ", " << b.run.iterations << " iterations in "
                  << std::setprecision(4) << b.run.seconds << " s, rank peak " << b.run.rankPeakRssMiB << " MiB\n";
    }
    std::cout << "  merge:           " << std::setprecision(4) << bricked.mergeSeconds << " s\n";
}

/// What the ingested grid holds in place of the voxels its threshold dropped.
std::string thresholdNote(const VolumeMetadata& source) {
    if (!source.threshold) return "";
    std::ostringstream note;
    note << " (voxels at or below " << *source.threshold << " at its background)";
    return note.str();
}

/// The residual layer, as --json reports it.
nlohmann::json layerJson(const BoundedLayerReport& layer) {
    return {{"max_error", layer.bound},
            {"measured_max_error", layer.maxError},
            {"searched_for_ratio", layer.searchedRatio > 0.0 ? nlohmann::json(layer.searchedRatio) : nlohmann::json()},
            {"encodes", layer.encodes},
            {"domain", layer.integers ? "stored samples" : "values"},
            {"exact_voxels", layer.exactVoxels},
            {"gaussian_bytes", layer.gaussianBytes},
            {"layer_bytes", layer.fileBytes - layer.gaussianBytes},
            {"seconds", layer.seconds}};
}

void reportLayer(const BoundedLayerReport& layer, std::uint64_t rawBytes) {
    if (layer.searchedRatio > 0.0) {
        std::cout << "  bound search:    the smallest bound with which the asset fits " << std::setprecision(4)
                  << layer.searchedRatio << ":1 is " << std::setprecision(6) << layer.bound << " (" << layer.encodes
                  << " layers encoded)\n";
    }
    std::cout << "  residual layer:  every voxel within " << layer.bound
              << " of the source as read (measured: " << layer.maxError << "), coded in "
              << (layer.integers ? "its stored samples" : "float values") << ", " << layer.exactVoxels
              << " voxels stored exactly; " << formatBytes(layer.fileBytes - layer.gaussianBytes) << " in "
              << std::setprecision(3) << layer.seconds
              << " s. The Gaussians alone (--layers gaussians): " << std::setprecision(4)
              << double(rawBytes) / double(layer.gaussianBytes) << ":1\n";
}

void report(const FitFlags& flags, const BudgetedFitResult& result, double peak, const FieldAccuracy& error,
            const TeamFitResult* bricked, const PhaseTimes& phases, const BoundedLayerReport* layer = nullptr) {
    const GaussianAsset& asset = result.asset;
    const FitReport& fit = result.fit;
    const std::uint64_t fileBytes = std::filesystem::file_size(flags.output);
    const std::uint64_t rawBytes = asset.source.rawSourceBytes();
    const std::uint64_t floatBytes = std::uint64_t(asset.source.dims.x()) * asset.source.dims.y() *
                                     asset.source.dims.z() * asset.source.channels * 4;
    const std::string undertrained = undertrainedNote(result, flags.options.settings, "--min-samples");
    if (!undertrained.empty()) diagnostics() << "gvr: warning: " << undertrained << "\n";
    const std::string overran = overrunNote(phases, fit, flags.options.settings.seconds);
    if (!overran.empty()) diagnostics() << "gvr: warning: " << overran << "\n";
    if (flags.json) {
        nlohmann::json out = {
            {"output", flags.output},
            {"gaussians", asset.params.count()},
            {"file_bytes", fileBytes},
            {"raw_source_bytes", rawBytes},
            {"ratio_vs_raw", double(rawBytes) / fileBytes},
            {"ratio_vs_float32", double(floatBytes) / fileBytes},
            {"iterations", fit.iterations},
            {"seconds", fit.seconds},
            {"setup_seconds", fit.setupSeconds},
            {"voxel_samples", fit.voxelSamples},
            {"voxel_samples_per_second", fit.adamSeconds > 0.0 ? fit.voxelSamples / fit.adamSeconds : 0.0},
            {"mean_gradient_share", fit.meanGradientShare},
            {"psnr_db", jsonNumber(error.psnr)},
            {"fg_psnr_db", jsonNumber(error.foregroundPsnr)},
            {"peak", peak},
            {"skipped_steps", fit.skippedSteps},
            {"pruned", fit.pruned},
            {"respawned", fit.respawned},
            {"added_to_fill_budget", fit.added},
            {"amplitude_solve", amplitudeSolveJson(fit, peak)},
            {"dropped_to_fit_budget", result.dropped},
            {"peak_rss_mib", peakRssMiB()},
            {"gaussians_allowed_by_ratio", fit.requestedGaussians},
            {"voxel_samples_per_gaussian", samplesPerGaussian(result)},
            {"undertrained", undertrained.empty() ? nlohmann::json() : nlohmann::json(undertrained)},
            {"phase_seconds", phases.json()}};
        if (!result.structures.empty()) out["structures"] = structuresJson(asset, result.structures);
        out["residual_layer"] = layer ? layerJson(*layer) : nlohmann::json();
        if (bricked) {
            out["bricks"] = bricksJson(bricked->bricks);
            out["merge_seconds"] = bricked->mergeSeconds;
            out["seam_voxels"] = error.markedVoxels;
            out["seam_psnr_db"] = jsonNumber(error.markedPsnr);
            out["interior_psnr_db"] = jsonNumber(error.unmarkedPsnr);
            out["seam_fg_psnr_db"] = jsonNumber(error.markedForegroundPsnr);
            out["interior_fg_psnr_db"] = jsonNumber(error.unmarkedForegroundPsnr);
        }
        std::cout << jsonText(out, 2) << "\n";
        return;
    }
    std::cout << "wrote " << flags.output << ": " << asset.params.count() << " Gaussians, " << formatBytes(fileBytes)
              << "\n"
              << "  compression:     " << std::setprecision(4) << double(rawBytes) / fileBytes
              << ":1 against the raw source (" << formatBytes(rawBytes) << "), " << double(floatBytes) / fileBytes
              << ":1 against float32\n"
              << "  fit:             " << fit.iterations << " iterations in " << std::setprecision(4) << fit.seconds
              << " s (set-up " << fit.setupSeconds << " s); " << fit.skippedSteps << " steps skipped (non-finite), "
              << fit.pruned << " Gaussians pruned, " << fit.respawned << " respawned, " << fit.added
              << " added where the file had room\n";
    if (layer) reportLayer(*layer, rawBytes);
    if (fit.requestedGaussians > 0) {
        std::cout << "  count:           fewer Gaussians than the ratio allows (" << fit.requestedGaussians
                  << "), as --min-samples " << flags.options.settings.minSamplesPerGaussian
                  << " asked: the time budget gives about that many voxel samples to each of fewer\n";
    }
    std::cout << "  amplitude solve: ";
    if (!fit.amplitudeSolveSkipped.empty()) {
        std::cout << "skipped: " << fit.amplitudeSolveSkipped;
    } else {
        std::cout << fit.amplitudeSolve.iterations << " CG iterations in " << fit.amplitudeSolve.seconds << " s";
    }
    if (fit.amplitudeSolve.mseBefore > 0.0) {
        std::cout << ", dense PSNR " << formatDb(psnrFromMse(fit.amplitudeSolve.mseBefore, peak)) << " -> "
                  << formatDb(psnrFromMse(fit.amplitudeSolve.mseAfter, peak))
                  << " dB (geometry as stored, amplitudes not yet rounded)";
    }
    std::cout << "\n"
              << "  PSNR (as saved): " << formatDb(error.psnr) << " dB against the ingested grid"
              << thresholdNote(asset.source) << ", " << formatDb(error.foregroundPsnr) << " dB over its "
              << error.foregroundVoxels << " active voxels; peak " << peak
              << ", its data range in the fit's units; "
                 "gvr eval SOURCE ASSET compares with the source as read\n"
              << "  peak memory:     " << std::setprecision(5) << peakRssMiB() << " MiB\n"
              << "  wall time:       " << phases.text() << "\n";
    for (const nlohmann::json& st : structuresJson(asset, result.structures)) {
        std::cout << "  structure " << st["id"] << " " << st["name"].get<std::string>() << ": " << st["voxels"]
                  << " voxels, " << st["gaussians"] << " Gaussians\n";
    }
    if (bricked) reportBricks(*bricked, error);
}

/// The fit the flags ask for; FitJob checks it again, cheaply.
/// @throw InputError for bad flags, before anything is read.
FitRequest requestOf(const FitFlags& flags) {
    FitRequest request;
    request.options = flags.options;
    // --time covers the measurement the report makes; a bricked fit's bricks have their own budgets.
    request.options.settings.reserveMeasurement = !flags.bricks.any();
    if (!flags.maxError.empty()) {
        request.bound = BoundRequest{flags.maxError, flags.ratioGiven ? flags.options.ratio : 0.0};
    }
    request.bricks = flags.bricks.options();
    return checkedFitRequest(std::move(request));
}

/// The input read (ingested first unless it is a .vdb), its warnings printed.
/// @param vdbOnDemand  a .vdb's voxels are read as they are first touched
FitJob readInput(const FitFlags& flags, const FitRequest& request, bool vdbOnDemand) {
    FitInput input;
    input.path = flags.input;
    input.ingest = toIngestOptions(flags.source);
    input.ingest.labels = flags.labelVolume;
    input.ingest.labelNames = flags.labelNames;
    input.ingest.vdbOnDemand = vdbOnDemand;
    FitJob job(std::move(input), request);
    for (const std::string& warning : job.warnings())
        diagnostics() << "gvr: warning: " << inCommandLineTerms(warning) << "\n";
    return job;
}

/// --brick I --of N: the part, written as it is, and what it holds.
void writePart(const FitFlags& flags, const FitJob& job) {
    const std::size_t index = *flags.bricks.only;
    GaussianAsset part;
    {
        ProgressBar bar("fitting", !flags.quiet);
        part = fitOneBrick(job.loaded().grid, job.target(), job.name(), job.request().options, job.request().bricks,
                           index, brickObserver(bar, index));
    }
    writeAsset(flags.output, part);
    const BrickRun run = brickRunOf(part, flags.output);
    if (flags.json) {
        const nlohmann::json report{{"output", flags.output},       {"brick", index},
                                    {"of", flags.bricks.count},     {"gaussians", part.params.count()},
                                    {"iterations", run.iterations}, {"seconds", run.seconds},
                                    {"peak_rss_mib", peakRssMiB()}};
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    std::cout << "wrote " << flags.output << ": brick " << index << " of " << flags.bricks.count << ", "
              << part.params.count() << " Gaussians, " << run.iterations << " iterations in " << std::setprecision(4)
              << run.seconds << " s; join the parts with gvr merge\n";
}

/// --bricks N, alone or across the ranks of an mpirun: rank 0 merges, writes and
/// reports; every rank measures the saved asset's error on its own bricks. Ranks
/// of a team read a .vdb input on demand, so each holds little more than its bricks.
void runBrickedFit(const FitFlags& flags, const FitRequest& request, PhaseTimes& phases) {
    const std::unique_ptr<BrickTeam> joined = teamOfThisLaunch(reportTeamError);
    const BrickTeam& team = *joined;
    const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, team.threadsPerRank());
    const FitJob job = readInput(flags, request, /*vdbOnDemand=*/team.size() > 1);
    phases.lap("load");
    TeamFitResult bricked;
    std::string saved;  // the asset's bytes as written; empty while rank 0 has none
    try {
        bricked = fitAllBricks(team, job.loaded().grid, job.target(), job.name(), request.options, request.bricks,
                               brickBars(!flags.quiet));
        phases.lap("fit");
        if (team.isRoot()) {
            saved = encodeAsset(bricked.result.asset);
            writeAssetBytes(flags.output, saved);
        }
        phases.lap("write");
    } catch (const std::exception&) {
        std::string none;
        if (team.isRoot()) team.broadcast(none);  // the others stop waiting; this rank says why
        throw;
    }
    team.broadcast(saved);
    if (saved.empty()) return;
    ProgressBar measuring("measuring", !flags.quiet && team.isRoot());
    const FieldAccuracy error = measureAcrossTeam(team, saved, job.target(), bricked, measuring.callback());
    phases.lap("measure");
    if (team.isRoot()) report(flags, bricked.result, job.target().peak(), error, &bricked, phases);
}

void runFit(const FitFlags& flags) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                flags.threads > 0 ? flags.threads : tbb::this_task_arena::max_concurrency());
    const FitRequest request = requestOf(flags);
    checkOutputPath("-o", flags.output, {flags.input, flags.labelVolume, flags.labelNames});
    if (!flags.logPath.empty()) {
        checkOutputPath("--log", flags.logPath, {flags.input, flags.output, flags.labelVolume, flags.labelNames});
    }

    PhaseTimes phases;
    if (flags.bricks.any() && !flags.bricks.only) return runBrickedFit(flags, request, phases);
    const FitJob job = readInput(flags, request, /*vdbOnDemand=*/false);
    phases.lap("load");
    if (flags.bricks.only) return writePart(flags, job);

    FitLog log(flags.logPath, phases.total());
    FitOutcome outcome;
    {
        FitBars bars(!flags.quiet);
        outcome = job.run(bars.observers(log), &phases);
    }
    const BudgetedFitResult& result = outcome.result;
    writeAssetBytes(flags.output, result.file);
    log.finish();
    phases.lap("write");
    ProgressBar measuring("measuring", !flags.quiet);
    const GaussianField saved(quantisedCopy(result.asset.params, result.asset.encoding), result.asset.cutoffSigmas);
    const FieldAccuracy error =
        measureFieldAccuracy(saved, job.target(), measuring.callback(), {}, defaultExportCut(result.asset));
    phases.lap("measure");
    report(flags, result, job.target().peak(), error, nullptr, phases, outcome.layer ? &*outcome.layer : nullptr);
}

void addBrickFlags(CLI::App& command, BrickFlags& flags) {
    auto* bricks =
        command
            .add_option("--bricks", flags.count,
                        "Fit in N bricks of whole 8^3 leaves, each with its own seed and a share of the Gaussians in "
                        "proportion to its active voxels, then merge them into one asset. Under mpirun the ranks "
                        "share the bricks and rank 0 writes")
            ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20));
    command.add_option("--halo", flags.halo, "Voxels around a brick that its fit also sees")
        ->check(CLI::Range(0, 256))
        ->capture_default_str();
    auto* only =
        command
            .add_option("--brick", flags.only,
                        "Fit only brick I of --of N and write it as a part, for a job array; gvr merge joins the parts")
            ->excludes(bricks);
    command.add_option("--of", flags.count, "With --brick: the number of bricks")
        ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20))
        ->needs(only);
    only->needs("--of");
}

void addTuningFlags(CLI::App& command, FitSettings& s) {
    command.option_defaults()->group("Sampling (the block engine)");
    command
        .add_option("--batch", s.voxelBatch,
                    "Voxel samples per iteration (expected), in whole 8^3 blocks drawn by error (0: 8 a Gaussian, at "
                    "least 524288)")
        ->capture_default_str();
    command
        .add_option("--row-stride", s.rowStride, "Evaluate every k-th row (along z) of a drawn block, weighted by k")
        ->capture_default_str();
    command.add_option("--refresh-every", s.refreshEvery, "K: redraw the blocks every K iterations")
        ->capture_default_str();
    command.add_option("--rebin-every", s.rebinEvery, "Iterations between binning every Gaussian to its blocks afresh")
        ->capture_default_str();
    command
        .add_option("--min-samples", s.minSamplesPerGaussian,
                    "With --ratio and --time: trade Gaussians for training, fitting fewer than the ratio allows "
                    "(so a higher ratio) when the time cannot give each about this many voxel samples, measured "
                    "over the first iterations (0: never; the file keeps the ratio)")
        ->capture_default_str();
    command
        .add_option("--mc-lambda", s.importance.uniformShare,
                    "lambda: uniform share of p(x) = lambda/n + (1-lambda) p_imp(x)")
        ->capture_default_str();
    command.add_option("--mc-epsilon", s.importance.epsilon, "epsilon added to each block's error in p_imp")
        ->capture_default_str();
    command.option_defaults()->group("Slice curriculum");
    command.add_option("--slice-pixels", s.slicePixels, "Pixels per random slice")->capture_default_str();
    command.add_option("--slice-max", s.sliceMax, "lambda_s,max of the slice curriculum")->capture_default_str();
    command.add_option("--slice-gamma", s.sliceGamma, "gamma_s: curriculum midpoint, as a fraction of the budget")
        ->capture_default_str();
    command.add_option("--slice-beta", s.sliceBeta, "beta_s: curriculum width, as a fraction of the budget")
        ->capture_default_str();
    command.option_defaults()->group("Optimiser (Adam)");
    command.add_option("--lr", s.learningRate, "Base Adam learning rate (the paper's 5e-4), scaled per group")
        ->capture_default_str();
    command.add_option("--lr-final", s.finalRateFactor, "Learning rates decay exponentially to this factor")
        ->capture_default_str();
    command.option_defaults()->group("Seeding and pruning");
    command.add_option("--gradient-share", s.gradientSeedShare, "Share of seeds drawn by gradient magnitude")
        ->capture_default_str();
    command.add_option("--uniform-share", s.uniformSeedShare, "Share of seeds drawn uniformly")->capture_default_str();
    command.add_option("--cutoff", s.cutoffSigmas, "Truncation radius of every Gaussian, in standard deviations")
        ->capture_default_str();
    command.add_option("--prune-every", s.pruneEvery, "Iterations between prune-and-respawn passes (0: never)")
        ->capture_default_str();
    command
        .add_option("--prune-amplitude", s.pruneAmplitude, "Prune Gaussians whose peak |opacity*colour| is below this")
        ->capture_default_str();
    command.option_defaults()->group("Amplitude solve");
    command
        .add_option("--solve-iterations", s.amplitudeSolveIterations,
                    "Conjugate-gradient iterations of the final least-squares amplitude solve (0: none)")
        ->capture_default_str();
    command.add_option("--solve-share", s.amplitudeSolveShare, "Share of a --time budget kept for the amplitude solve")
        ->capture_default_str();
    command.option_defaults()->group("Error-against-time curve");
    command.add_option("--held-out", s.heldOutVoxels, "Fixed voxels for the PSNR curve")->capture_default_str();
    command.add_option("--log-every", s.logEvery, "Iterations between PSNR evaluations")->capture_default_str();
}

void addEncodingFlags(CLI::App& command, AssetEncoding& e) {
    command.option_defaults()->group("Asset encoding");
    command.add_option("--mean-step", e.meanStep, "Asset: lattice of the stored means, in voxels")
        ->check(CLI::Range(1e-4, 8.0))
        ->capture_default_str();
    command.add_option("--rotation-bits", e.rotationBits, "Asset: bits per stored quaternion component")
        ->check(CLI::Range(2, 15))
        ->capture_default_str();
    command.add_option("--scale-bits", e.logScaleBits, "Asset: bits per log-scale")
        ->check(CLI::Range(2, 16))
        ->capture_default_str();
    command.add_option("--amplitude-bits", e.amplitudeBits, "Asset: bits per amplitude (opacity x colour) channel")
        ->check(CLI::Range(2, 16))
        ->capture_default_str();
}

}  // namespace

void addFitCommand(CLI::App& app) {
    auto flags = std::make_shared<FitFlags>();
    flags->options.settings.seconds = kDefaultFitSeconds;
    CLI::App* command =
        app.add_subcommand("fit",
                           "Fit Gaussians to a volume (a .vdb from ingest, or any input ingest reads) and write a "
                           "Gaussian asset. Ablations: full = Monte Carlo importance voxels then the slice curriculum; "
                           "A1 = uniform random voxels; A2 = uniform voxels then slices; A3 = slices then voxels; "
                           "A4 = slices only; A5 = Monte Carlo voxels only");
    command->add_option("input", flags->input, "Grid (.vdb) or source volume")->required();
    command->option_defaults()->group("Budget and output");
    command->add_option("-o,--output", flags->output, "Asset file to write (any name)")->required();
    auto* ratio =
        command
            ->add_option("--ratio", flags->options.ratio,
                         "Target compression ratio against the raw source bytes (with --max-error E, of the "
                         "Gaussians alone, default there " +
                             std::to_string(int(kBoundedPreviewRatio)) + "; with --max-error auto, of the whole asset)")
            ->capture_default_str()
            ->each([flags](const std::string&) { flags->ratioGiven = true; });
    command->add_option("--gaussians", flags->options.gaussians, "Fit exactly this many Gaussians instead")
        ->excludes(ratio)
        ->check(CLI::Range(std::size_t(1), std::size_t(1) << 32));
    auto* time =
        command->add_option("--time", flags->options.settings.seconds, "Time budget in seconds")->capture_default_str();
    command
        ->add_option("--iterations", flags->options.settings.iterations,
                     "Iteration budget; with it the result is reproducible byte for byte")
        ->excludes(time)
        ->each([flags](const std::string&) { flags->options.settings.seconds = 0.0; });
    auto* maxError = command->add_option(
        "--max-error", flags->maxError,
        "Add a residual layer so that every voxel of the export is within E of the source as read: "
        "E in the source's units (HU, the stored values), or a percentage of its data range (0.5%). "
        "Integer data at E < 1 is kept losslessly. --ratio then sizes the Gaussians, the preview "
        "(default " +
            std::to_string(int(kBoundedPreviewRatio)) +
            ":1); the layer adds what the bound needs. "
            "auto, with --ratio R: the smallest bound with which the whole asset fits R (the Gaussians at "
            "R x 4, at least " +
            std::to_string(int(kBoundedPreviewRatio)) + ":1), printed");
    command->add_option("--seed", flags->options.settings.seed, "Random seed")->capture_default_str();
    command->add_option("--ablation", flags->options.ablation, "full, A1, A2, A3, A4 or A5")->capture_default_str();
    auto* log = command->add_option("--log", flags->logPath, "Write error against run time as CSV");
    command->option_defaults()->group("Structures (atlas labels)");
    auto* labels = command->add_option(
        "--labels", flags->options.labels,
        "Fit by structure from the label grid that ingest --labels stored (or --label-volume): all, "
        "or IDs and names "
        "(comma-separated). Each structure gets Gaussians in proportion to its voxels (at least " +
            std::to_string(kStructureFloor) +
            "), its own samples and seed; other voxels are "
            "left out. --ratio then applies to each structure's own voxels");
    auto* labelVolume =
        command
            ->add_option("--label-volume", flags->labelVolume,
                         "With --labels: the label volume (an atlas such as aal.nii.gz, anything ingest reads) on "
                         "the input's voxels, when the input is not a .vdb from ingest --labels")
            ->needs(labels);
    command
        ->add_option("--label-names", flags->labelNames,
                     "With --label-volume: names of its labels, one \"ID NAME\" per line (AAL .txt, FreeSurfer LUT)")
        ->needs(labelVolume);
    command->option_defaults()->group("Budget and output");
    command->add_option("--threads", flags->threads, "Worker threads (default: all cores)")->check(CLI::Range(0, 1024));
    command->option_defaults()->group("Bricks (large volumes, MPI, job arrays)");
    addBrickFlags(*command, flags->bricks);
    command->get_option("--bricks")->excludes(log)->excludes(labels)->excludes(maxError);
    command->get_option("--brick")->excludes(maxError);
    command->get_option("--brick")->excludes(log)->excludes(labels);
    addTuningFlags(*command, flags->options.settings);
    addEncodingFlags(*command, flags->options.encoding);
    command->option_defaults()->group("Reading a source volume (as gvr ingest)");
    addSourceFlags(*command, flags->source);
    command->option_defaults()->group("Budget and output");
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->add_flag("-q,--quiet", flags->quiet, "No progress bars");
    command->callback([flags] { runFit(*flags); });
}

}  // namespace gvr
