#include "workflow/TeamFit.h"

#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "pipeline/GaussianField.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <optional>

namespace gvr {

namespace {

using Clock = std::chrono::steady_clock;

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

GaussianAsset fitPart(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const BrickPlan& plan,
                      std::size_t index, double seconds, int rank, const FitObserver& observer) {
    if (brickMadeToFail() == index)
        throw InputError("GVR_TEST_FAIL_BRICK", "brick " + std::to_string(index) + " failed on purpose");
    return fitBrickPart(grid, name, plan, index, seconds, observer, rank);
}

std::vector<std::size_t> bricksOf(int rank, const std::vector<int>& owners) {
    std::vector<std::size_t> mine;
    for (std::size_t b = 0; b < owners.size(); ++b) {
        if (owners[b] == rank) mine.push_back(b);
    }
    return mine;
}

std::vector<BrickOutcome> fitMine(const openvdb::GridBase::ConstPtr& grid, const std::string& name,
                                  const BrickPlan& plan, const std::vector<std::size_t>& mine, int rank,
                                  const BrickObservers& observers) {
    std::vector<BrickOutcome> outcomes;
    for (std::size_t b : mine) {
        BrickOutcome outcome{b, rank, true, {}};
        try {
            const FitObserver observer = observers ? observers(b) : FitObserver{};
            GaussianAsset part = fitPart(grid, name, plan, b, brickSeconds(plan, mine, b), rank, observer);
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
        const std::string name =
            "brick " + std::to_string(outcome.brick) + " (rank " + std::to_string(outcome.rank) + ")";
        if (!outcome.ok) throw InputError(name, outcome.bytes);
        parts.push_back(decodeAsset(outcome.bytes, name));
        names.push_back(name);
    }
    return parts;
}

/// The merged asset and report; @a layout gives each brick's budget.
TeamFitResult merged(std::vector<GaussianAsset> parts, const std::vector<std::string>& names,
                     const std::vector<Brick>& layout) {
    TeamFitResult out;
    FitReport& total = out.result.fit;
    for (std::size_t p = 0; p < parts.size(); ++p) {
        const std::size_t brick = brickOfPart(parts[p], names[p]).first;
        const BrickRun run = brickRunOf(parts[p], names[p]);
        out.bricks.push_back({brick, layout.at(brick).budget, run});
        total.iterations += run.iterations;
        total.seconds += run.seconds;
        total.pruned += run.pruned;
        total.respawned += run.respawned;
        total.amplitudeSolve.iterations += run.solveIterations;
        total.amplitudeSolve.seconds += run.solveSeconds;
    }
    const auto start = Clock::now();
    out.result.asset = mergeBrickParts(std::move(parts), names, &out.result.dropped);
    out.mergeSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    return out;
}

}  // namespace

TeamFitResult fitAllBricks(const BrickTeam& team, const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target,
                           const std::string& name, const BudgetedFitOptions& options, const BrickOptions& bricks,
                           const BrickObservers& observers) {
    std::vector<BrickOutcome> outcomes;
    TeamFitResult result;
    try {
        const BrickPlan plan = planBrickedFit(target, name, options, bricks);
        const std::vector<int> owners = team.owners(plan.bricks);
        const std::vector<std::size_t> mine = bricksOf(team.rank(), owners);
        outcomes = fitMine(grid, name, plan, mine, team.rank(), team.isRoot() ? observers : BrickObservers{});
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
    TeamFitResult merge = merged(std::move(parts), names, result.layout);
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
std::vector<BrickOutcome> measureMine(const GaussianField& field, const ThresholdCut& cut, const VolumeTarget& target,
                                      const TeamFitResult& fit, const std::vector<std::size_t>& mine, int rank,
                                      const ProgressFn& progress) {
    const BrickSeams seams(fit.layout, kSeamWidth);
    const VoxelMarking nearFace = [&](const openvdb::Coord& ijk) { return seams.near(ijk); };
    std::vector<BrickOutcome> outcomes;
    for (std::size_t n = 0; n < mine.size(); ++n) {
        const ProgressFn share = [&](double fraction) {
            if (progress) progress((double(n) + fraction) / double(mine.size()));
        };
        const Brick& brick = fit.layout[mine[n]];
        outcomes.push_back(
            {brick.index, rank, true, bytesOf(measureSliceSums(field, target, brick.core, share, nearFace, cut))});
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
                                const TeamFitResult& fit, const ProgressFn& progress) {
    try {
        const GaussianAsset asset = decodeAsset(saved, "the merged asset");
        const GaussianField field(quantisedCopy(asset.params, asset.encoding), asset.cutoffSigmas);
        std::vector<BrickOutcome> outcomes =
            measureMine(field, defaultExportCut(asset), target, fit, bricksOf(team.rank(), fit.owners), team.rank(),
                        team.isRoot() ? progress : ProgressFn{});
        outcomes = team.gather(std::move(outcomes), fit.owners);
        return team.isRoot() ? fieldAccuracyOf(wholeBoxSlices(outcomes, fit.layout, target), target) : FieldAccuracy{};
    } catch (const std::exception& error) {
        team.abortUnlessAlone(error);  // the others would wait in the gather
        throw;
    }
}

GaussianAsset fitOneBrick(const openvdb::GridBase::ConstPtr& grid, const VolumeTarget& target, const std::string& name,
                          const BudgetedFitOptions& options, const BrickOptions& bricks, std::size_t index,
                          const FitObserver& observer) {
    const BrickPlan plan = planBrickedFit(target, name, options, bricks);
    if (index >= plan.bricks.size()) {
        throw InputError("`brick`",
                         std::to_string(index) + " is not below `of=" + std::to_string(plan.bricks.size()) + "`");
    }
    return fitPart(grid, name, plan, index, plan.settings.seconds, 0, observer);
}

}  // namespace gvr
