#include "FitBricks.h"

#include "AssetFile.h"
#include "BrickTeam.h"
#include "Error.h"
#include "GaussianField.h"
#include "ProgressBar.h"
#include "Report.h"

#include <chrono>
#include <cstdlib>
#include <cstring>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

FitObserver barObserver(ProgressBar& bar, std::size_t brick) {
    return [&bar, brick](const FitProgress& p) {
        bar.update(p.fraction, "brick " + std::to_string(brick) + ", it " + std::to_string(p.iteration) + ", " +
                                   std::to_string(p.gaussians) + " Gaussians");
    };
}

/// The brick that tests make fail, from the environment (GVR_TEST_FAIL_BRICK): no
/// input makes one brick of a team fail on demand, and a hook there is no flag of gvr's.
std::optional<std::size_t> brickMadeToFail() {
    const char* text = std::getenv("GVR_TEST_FAIL_BRICK");
    if (!text || !*text) return std::nullopt;
    char* end = nullptr;
    const unsigned long long brick = std::strtoull(text, &end, 10);
    if (*end != '\0') return std::nullopt;
    return std::size_t(brick);
}

/// Fits brick @a index into a part; the part's brick record also tells how the
/// fit went (the merge drops the record).
GaussianAsset fitPart(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const BrickPlan& plan,
                      std::size_t index, double seconds, const BrickFlags& flags, int rank, bool progress) {
    if (brickMadeToFail() == index) throw InputError("GVR_TEST_FAIL_BRICK", "brick " + std::to_string(index) + " failed on purpose");
    ProgressBar bar("fitting", progress);
    FitReport report;
    GaussianAsset part = fitBrickPart(grid, name, plan, index, seconds, barObserver(bar, index), &report);
    part.fitSettings["brick"]["run"] = {{"rank", rank},
                                        {"gaussians", part.params.count()},
                                        {"iterations", report.iterations},
                                        {"seconds", report.seconds},
                                        {"pruned", report.pruned},
                                        {"respawned", report.respawned},
                                        {"solve_iterations", report.amplitudeSolve.iterations},
                                        {"solve_seconds", report.amplitudeSolve.seconds},
                                        {"rank_peak_rss_mib", peakRssMiB()}};
    return part;
}

std::vector<std::size_t> bricksOf(int rank, const std::vector<int>& owners) {
    std::vector<std::size_t> mine;
    for (std::size_t b = 0; b < owners.size(); ++b) {
        if (owners[b] == rank) mine.push_back(b);
    }
    return mine;
}

std::vector<BrickOutcome> fitMine(const openvdb::GridBase::ConstPtr& grid, const std::string& name,
                                  const BrickPlan& plan, const std::vector<std::size_t>& mine,
                                  const BrickFlags& flags, int rank, bool progress) {
    std::vector<BrickOutcome> outcomes;
    for (std::size_t b : mine) {
        BrickOutcome outcome{b, rank, true, {}};
        try {
            GaussianAsset part = fitPart(grid, name, plan, b, brickSeconds(plan, mine, b), flags, rank, progress);
            outcome.bytes = encodeAsset(part);
        } catch (const std::exception& error) {
            outcome.ok = false;
            outcome.bytes = error.what();
        }
        outcomes.push_back(std::move(outcome));
    }
    return outcomes;
}

/// The parts of all outcomes, or the first failure, named by brick and rank.
std::vector<GaussianAsset> partsOf(const std::vector<BrickOutcome>& outcomes, std::vector<std::string>& names) {
    std::vector<GaussianAsset> parts;
    for (const BrickOutcome& outcome : outcomes) {
        const std::string name = "brick " + std::to_string(outcome.brick) + " (rank " + std::to_string(outcome.rank) + ")";
        if (!outcome.ok) throw InputError(name, outcome.bytes);
        parts.push_back(decodeAsset(outcome.bytes, name));
        names.push_back(name);
    }
    return parts;
}

BrickedFitResult merged(std::vector<GaussianAsset> parts, const std::vector<std::string>& names) {
    BrickedFitResult out;
    FitReport& total = out.result.fit;
    for (const GaussianAsset& part : parts) {
        const nlohmann::json& brick = part.fitSettings.at("brick");
        const nlohmann::json& run = brick.at("run");
        out.bricks.push_back({{"brick", brick.at("index")}, {"budget", brick.at("budget")}, {"rank", run.at("rank")},
                              {"gaussians", run.at("gaussians")}, {"iterations", run.at("iterations")},
                              {"seconds", run.at("seconds")}, {"rank_peak_rss_mib", run.at("rank_peak_rss_mib")}});
        total.iterations += run.at("iterations").get<std::size_t>();
        total.seconds += run.at("seconds").get<double>();
        total.pruned += run.at("pruned").get<std::size_t>();
        total.respawned += run.at("respawned").get<std::size_t>();
        total.amplitudeSolve.iterations += run.at("solve_iterations").get<std::size_t>();
        total.amplitudeSolve.seconds += run.at("solve_seconds").get<double>();
    }
    const auto start = Clock::now();
    out.result.asset = mergeBrickParts(std::move(parts), names, &out.result.dropped);
    out.mergeSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

}  // namespace

void addBrickFlags(CLI::App& command, BrickFlags& flags) {
    auto* bricks = command.add_option("--bricks", flags.count,
                        "Fit in N bricks of whole 8^3 leaves, each with its own seed and a share of the Gaussians in "
                        "proportion to its active voxels, then merge them into one asset. Under mpirun the ranks "
                        "share the bricks and rank 0 writes")
        ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20));
    command.add_option("--halo", flags.halo, "Voxels around a brick that its fit also sees")
        ->check(CLI::Range(0, 256))->capture_default_str();
    auto* only = command.add_option("--brick", flags.only,
                        "Fit only brick I of --of N and write it as a part, for a job array; gvr merge joins the parts")
        ->excludes(bricks);
    command.add_option("--of", flags.count, "With --brick: the number of bricks")
        ->check(CLI::Range(std::size_t(1), std::size_t(1) << 20))->needs(only);
    only->needs("--of");
}

BrickedFitResult fitAllBricks(const BrickTeam& team, const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                              const std::string& name, const CompressOptions& options, const BrickFlags& flags,
                              bool progress) {
    std::vector<BrickOutcome> outcomes;
    BrickedFitResult result;
    try {
        const BrickPlan plan = planBrickedFit(target, name, options, {flags.count, flags.halo});
        const std::vector<int> owners = team.owners(plan.bricks);
        const std::vector<std::size_t> mine = bricksOf(team.rank(), owners);
        outcomes = fitMine(grid, name, plan, mine, flags, team.rank(), progress && team.isRoot());
        outcomes = team.gather(std::move(outcomes), owners);
        result.layout = plan.bricks;
        result.owners = owners;
    } catch (const std::exception& error) {
        team.abortUnlessAlone(error);  // before the gather, the other ranks would wait for this one forever
        throw;
    }
    if (!team.isRoot()) return result;
    std::vector<std::string> names;
    std::vector<GaussianAsset> parts = partsOf(outcomes, names);
    BrickedFitResult merge = merged(std::move(parts), names);
    merge.layout = std::move(result.layout);
    merge.owners = std::move(result.owners);
    return merge;
}

namespace {

std::string bytesOf(const std::vector<SliceSums>& slices) {
    return std::string(reinterpret_cast<const char*>(slices.data()), slices.size() * sizeof(SliceSums));
}

std::vector<SliceSums> slicesOf(const std::string& bytes) {
    std::vector<SliceSums> slices(bytes.size() / sizeof(SliceSums));
    std::memcpy(slices.data(), bytes.data(), slices.size() * sizeof(SliceSums));
    return slices;
}

/// This rank's bricks' cores measured, one outcome per brick.
std::vector<BrickOutcome> measureMine(const GaussianField& field, const ThresholdCut& cut,
                                     const VolumeTarget& target, const BrickedFitResult& fit,
                                     const std::vector<std::size_t>& mine, int rank, bool progress) {
    const BrickSeams seams(fit.layout, kSeamWidth);
    const VoxelMarking nearFace = [&](const openvdb::Coord& ijk) { return seams.near(ijk); };
    ProgressBar bar("measuring", progress);
    std::vector<BrickOutcome> outcomes;
    for (std::size_t n = 0; n < mine.size(); ++n) {
        const auto share = [&](double fraction) { bar.update((double(n) + fraction) / double(mine.size())); };
        const Brick& brick = fit.layout[mine[n]];
        outcomes.push_back({brick.index, rank, true, bytesOf(measureSliceSums(field, target, brick.core, share, nearFace, cut))});
    }
    return outcomes;
}

/// Every brick core's slices added into the whole box's, in brick order: the same
/// sums, bit for bit, whichever rank measured which brick.
std::vector<SliceSums> wholeBoxSlices(const std::vector<BrickOutcome>& outcomes, const std::vector<Brick>& layout,
                                       const VolumeTarget& target) {
    std::vector<SliceSums> whole(std::size_t(target.box().dim().z()));
    for (const BrickOutcome& outcome : outcomes) {
        openvdb::CoordBBox core = layout[outcome.brick].core;
        core.intersect(target.box());
        const std::vector<SliceSums> slices = slicesOf(outcome.bytes);
        for (std::size_t s = 0; s < slices.size(); ++s) {
            whole[std::size_t(core.min().z() - target.box().min().z()) + s].add(slices[s]);
        }
    }
    return whole;
}

}  // namespace

FieldAccuracy measureAcrossTeam(const BrickTeam& team, const std::string& saved, const VolumeTarget& target,
                              const BrickedFitResult& fit, bool progress) {
    try {
        const GaussianAsset asset = decodeAsset(saved, "the merged asset");
        const GaussianField field(quantisedCopy(asset.params, asset.encoding), asset.cutoffSigmas);
        std::vector<BrickOutcome> outcomes = measureMine(field, defaultExportCut(asset), target, fit, bricksOf(team.rank(), fit.owners),
                                                         team.rank(), progress && team.isRoot());
        outcomes = team.gather(std::move(outcomes), fit.owners);
        return team.isRoot() ? fieldAccuracyOf(wholeBoxSlices(outcomes, fit.layout, target), target) : FieldAccuracy{};
    } catch (const std::exception& error) {
        team.abortUnlessAlone(error);  // the others would wait in the gather
        throw;
    }
}

GaussianAsset fitOneBrick(const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                          const std::string& name, const CompressOptions& options, const BrickFlags& flags,
                          bool progress) {
    const BrickPlan plan = planBrickedFit(target, name, options, {flags.count, flags.halo});
    const std::size_t index = *flags.only;
    if (index >= plan.bricks.size()) {
        throw InputError("--brick", std::to_string(index) + " is not below --of " + std::to_string(plan.bricks.size()));
    }
    return fitPart(grid, name, plan, index, plan.settings.seconds, flags, 0, progress);
}

}  // namespace gvr
