#include "workflow/BrickedFit.h"

#include "io/asset/AssetFile.h"
#include "pipeline/Error.h"
#include "pipeline/ProcessMemory.h"

#include <algorithm>

namespace gvr {

namespace {

/// Fine enough that the merge's rounding, not the part's, decides the result.
AssetEncoding partEncoding() {
    AssetEncoding fine;
    fine.meanStep = 1.0f / 512.0f;
    fine.rotationBits = 15;
    fine.logScaleBits = 16;
    fine.amplitudeBits = 16;
    fine.zstdLevel = 3;
    return fine;
}

nlohmann::json encodingJson(const AssetEncoding& e) {
    return {{"mean_step", e.meanStep},
            {"rotation_bits", e.rotationBits},
            {"scale_bits", e.logScaleBits},
            {"amplitude_bits", e.amplitudeBits},
            {"zstd_level", e.zstdLevel}};
}

/// @throw std::runtime_error for depths that `gvr fit` never writes.
AssetEncoding encodingFromJson(const nlohmann::json& json) {
    AssetEncoding e;
    e.meanStep = json.at("mean_step").get<float>();
    e.rotationBits = json.at("rotation_bits").get<int>();
    e.logScaleBits = json.at("scale_bits").get<int>();
    e.amplitudeBits = json.at("amplitude_bits").get<int>();
    e.zstdLevel = json.at("zstd_level").get<int>();
    const auto within = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
    if (!within(e.meanStep, 1e-4, 8.0) || !within(e.rotationBits, 2, 15) || !within(e.logScaleBits, 2, 16) ||
        !within(e.amplitudeBits, 2, 16) || !within(e.zstdLevel, 1, 22)) {
        throw std::runtime_error("encoding out of range");
    }
    return e;
}

nlohmann::json coordJson(const openvdb::Coord& c) { return {c.x(), c.y(), c.z()}; }

/// A part's record of its brick, and what the merge needs that only the plan knew.
nlohmann::json brickRecord(const BrickPlan& plan, const Brick& brick) {
    return {{"index", brick.index},
            {"of", plan.bricks.size()},
            {"core_min", coordJson(brick.core.min())},
            {"core_max", coordJson(brick.core.max())},
            {"budget", brick.budget},
            {"max_bytes", plan.maxBytes},
            {"encoding", encodingJson(plan.skeleton.encoding)}};
}

BrickRun runOf(const FitReport& report, std::size_t gaussians, int rank) {
    BrickRun run;
    run.rank = rank;
    run.gaussians = gaussians;
    run.iterations = report.iterations;
    run.seconds = report.seconds;
    run.pruned = report.pruned;
    run.respawned = report.respawned;
    run.solveIterations = report.amplitudeSolve.iterations;
    run.solveSeconds = report.amplitudeSolve.seconds;
    run.rankPeakRssMiB = peakRssMiB();
    return run;
}

/// The part's record of its run, in the keys that part files have always had
/// (gvr merge reads parts written by earlier versions).
nlohmann::json runRecord(const BrickRun& run) {
    return {{"rank", run.rank},
            {"gaussians", run.gaussians},
            {"iterations", run.iterations},
            {"seconds", run.seconds},
            {"pruned", run.pruned},
            {"respawned", run.respawned},
            {"solve_iterations", run.solveIterations},
            {"solve_seconds", run.solveSeconds},
            {"rank_peak_rss_mib", run.rankPeakRssMiB}};
}

/// The part's fit record without its brick: equal for all parts of one fit.
nlohmann::json sharedRecord(const GaussianAsset& part) {
    nlohmann::json shared = part.fitSettings;
    shared.erase("brick");
    return shared;
}

/// The part's record of the plan it shares with every other part: the brick count,
/// the whole byte budget (the ratio) and the encoding.
nlohmann::json planRecord(const GaussianAsset& part) {
    nlohmann::json plan = part.fitSettings.value("brick", nlohmann::json::object());
    for (const char* ownToTheBrick : {"index", "core_min", "core_max", "budget", "run"}) plan.erase(ownToTheBrick);
    return plan;
}

/// Refuses @a part when it belongs to another fit than @a first.
void checkSameFit(const GaussianAsset& first, const GaussianAsset& part, const std::string& name) {
    if (sharedRecord(part) != sharedRecord(first) || planRecord(part) != planRecord(first) ||
        part.params.channels != first.params.channels || part.cutoffSigmas != first.cutoffSigmas ||
        part.worldFromIndex != first.worldFromIndex || part.source.dims != first.source.dims ||
        part.mapping.scale != first.mapping.scale || part.mapping.offset != first.mapping.offset) {
        throw InputError(
            name, "is a brick of another fit (other volume, settings, ratio or brick count) than the first part");
    }
}

}  // namespace

BrickPlan planBrickedFit(const VolumeTarget& target, const std::string& name, const BudgetedFitOptions& options,
                         const BrickOptions& bricks) {
    if (bricks.count == 0) throw InputError("`bricks`", "must be at least 1");
    if (bricks.halo < 0) throw InputError("`halo`", "must be at least 0");
    if (!options.labels.empty()) throw InputError("`bricks`", "cannot be combined with `labels`");
    BrickPlan plan;
    plan.settings = checkedSettings(options);
    plan.halo = bricks.halo;
    plan.skeleton = assetSkeleton(target, plan.settings, options, name);
    plan.settings.gaussians = budgetedGaussians(plan.skeleton, options, plan.maxBytes);
    plan.lattice = brickLattice(target.box(), bricks.count);
    plan.skeleton.fitSettings["bricks"] = {
        {"count", bricks.count}, {"lattice", coordJson(plan.lattice)}, {"halo", bricks.halo}};
    plan.bricks = planBricks(target, plan.lattice, bricks.halo, plan.settings.gaussians);
    return plan;
}

double brickSeconds(const BrickPlan& plan, const std::vector<std::size_t>& mine, std::size_t index) {
    std::size_t sum = 0;
    for (std::size_t b : mine) sum += plan.bricks.at(b).budget;
    return sum == 0 ? 0.0 : plan.settings.seconds * double(plan.bricks.at(index).budget) / double(sum);
}

GaussianAsset fitBrickPart(const openvdb::GridBase::ConstPtr& grid, const std::string& name, const BrickPlan& plan,
                           std::size_t index, double seconds, const FitObserver& observer, int rank) {
    const Brick& brick = plan.bricks.at(index);
    FitSettings settings = plan.settings;
    if (settings.seconds > 0.0) settings.seconds = std::max(seconds, 1e-3);
    GaussianAsset part = plan.skeleton;
    FitReport report;
    part.params = fitBrick(grid, name, brick, settings, observer, &report);
    part.encoding = partEncoding();
    part.fitSettings["brick"] = brickRecord(plan, brick);
    part.fitSettings["brick"]["run"] = runRecord(runOf(report, part.params.count(), rank));
    return part;
}

BrickRun brickRunOf(const GaussianAsset& part, const std::string& name) {
    try {
        const nlohmann::json& run = part.fitSettings.at("brick").at("run");
        BrickRun out;
        out.rank = run.at("rank").get<int>();
        out.gaussians = run.at("gaussians").get<std::size_t>();
        out.iterations = run.at("iterations").get<std::size_t>();
        out.seconds = run.at("seconds").get<double>();
        out.pruned = run.at("pruned").get<std::size_t>();
        out.respawned = run.at("respawned").get<std::size_t>();
        out.solveIterations = run.at("solve_iterations").get<std::size_t>();
        out.solveSeconds = run.at("solve_seconds").get<double>();
        out.rankPeakRssMiB = run.at("rank_peak_rss_mib").get<double>();
        return out;
    } catch (const std::exception& error) {
        throw InputError(name, std::string("corrupt brick run record: ") + error.what());
    }
}

std::pair<std::size_t, std::size_t> brickOfPart(const GaussianAsset& part, const std::string& name) {
    if (!part.fitSettings.contains("brick")) {
        throw InputError(name, "is not a brick part (the asset of one brick of a bricked fit)");
    }
    try {
        const nlohmann::json& brick = part.fitSettings.at("brick");
        return {brick.at("index").get<std::size_t>(), brick.at("of").get<std::size_t>()};
    } catch (const std::exception& error) {
        throw InputError(name, std::string("corrupt brick record: ") + error.what());
    }
}

GaussianAsset mergeBrickParts(std::vector<GaussianAsset> parts, const std::vector<std::string>& names,
                              std::size_t* dropped) {
    if (parts.empty()) throw InputError("merge", "no parts given");
    const std::size_t of = brickOfPart(parts.front(), names.at(0)).second;
    std::vector<std::size_t> order(of, parts.size());
    for (std::size_t p = 0; p < parts.size(); ++p) {
        const auto [index, count] = brickOfPart(parts[p], names.at(p));
        checkSameFit(parts.front(), parts[p], names.at(p));
        if (count != of || index >= of)
            throw InputError(names.at(p), "is brick " + std::to_string(index) + " of " + std::to_string(count) +
                                              ", the first part says " + std::to_string(of) + " bricks");
        if (order[index] != parts.size())
            throw InputError(names.at(p),
                             "repeats brick " + std::to_string(index) + " (also in " + names.at(order[index]) + ")");
        order[index] = p;
    }
    std::string missing;
    for (std::size_t b = 0; b < of; ++b) {
        if (order[b] == parts.size()) missing += (missing.empty() ? "" : ", ") + std::to_string(b);
    }
    if (!missing.empty()) throw InputError("merge", "bricks " + missing + " of " + std::to_string(of) + " are missing");

    const nlohmann::json record = parts.front().fitSettings.at("brick");
    GaussianAsset merged = parts.front();
    merged.params = GaussianParameters(0, merged.params.channels);
    for (std::size_t b = 0; b < of; ++b) merged.params.append(parts[order[b]].params);
    merged.fitSettings = sharedRecord(merged);
    merged.formatVersion = 0;
    std::uint64_t maxBytes = 0;
    try {
        merged.encoding = encodingFromJson(record.at("encoding"));
        maxBytes = record.at("max_bytes").get<std::uint64_t>();
    } catch (const std::exception& error) {
        throw InputError(names.at(0), std::string("corrupt brick record: ") + error.what());
    }
    const std::size_t gone = fitAssetInto(merged, maxBytes);
    if (dropped) *dropped = gone;
    return merged;
}

}  // namespace gvr
