#include "pipeline/Initialisation.h"

#include "pipeline/GaussianBvh.h"
#include "pipeline/GaussianField.h"
#include "pipeline/LatticeSampler.h"
#include "pipeline/StreamSeed.h"
#include "pipeline/UniformVoxels.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <mutex>
#include <random>
#include <unordered_map>
#include <unordered_set>

namespace gvr {

namespace {

struct Keyed {
    double key;
    openvdb::Coord ijk;
    /// Equal keys (rare) order by coordinate, so that a union of candidates keeps
    /// the same ones whatever order they were offered in.
    bool operator>(const Keyed& other) const { return key > other.key || (key == other.key && other.ijk < ijk); }
};

/// Keeps the @a capacity entries with the largest keys. Entries are gathered and cut
/// down with nth_element whenever they reach twice the capacity, and after a cut
/// anything no larger than the smallest kept entry is turned away at once: linear
/// in what is offered, where a heap of a hundred thousand seeds cost a logarithm
/// per voxel.
class TopKeys {
public:
    explicit TopKeys(std::size_t capacity) : mCapacity(capacity) {}
    void offer(double key, const openvdb::Coord& ijk) {
        if (mCapacity == 0) return;
        const Keyed keyed{key, ijk};
        if (mCut && !(keyed > mSmallestKept)) return;
        mEntries.push_back(keyed);
        if (mEntries.size() >= 2 * mCapacity) keepLargest();
    }
    /// Every entry, in no order; none are left.
    std::vector<Keyed> take() {
        keepLargest();
        return std::move(mEntries);
    }
    /// Largest key first.
    std::vector<openvdb::Coord> takeSorted() {
        keepLargest();
        std::sort(mEntries.begin(), mEntries.end(), std::greater<Keyed>());
        std::vector<openvdb::Coord> coords(mEntries.size());
        for (std::size_t k = 0; k < coords.size(); ++k) coords[k] = mEntries[k].ijk;
        mEntries.clear();
        return coords;
    }

private:
    /// Keys are unique with their coordinates, so the kept set is the same in any order of offers.
    void keepLargest() {
        if (mEntries.size() <= mCapacity) return;
        const auto last = mEntries.begin() + std::ptrdiff_t(mCapacity - 1);
        std::nth_element(mEntries.begin(), last, mEntries.end(), std::greater<Keyed>());
        mEntries.resize(mCapacity);
        mSmallestKept = mEntries.back();
        mCut = true;
    }

    std::size_t mCapacity;
    std::vector<Keyed> mEntries;
    bool mCut = false;  ///< mEntries once held more than the capacity
    Keyed mSmallestKept{};
};

struct CoordHash {
    std::size_t operator()(const openvdb::Coord& c) const { return c.hash<20>(); }
};

/// Weighted sampling without replacement (Efraimidis-Spirakis): the largest keys
/// log(u)/w are a sample drawn with probability proportional to w. Uniform seeds
/// are stratified, one random active voxel per cell of a coarse grid sized for
/// about @a uniformCount occupied cells, so that they leave no large holes;
/// plain random voxels make up any shortfall.
/// Voxels per side of a stratification cell for @a uniformCount seeds.
int stratumSize(const VolumeTarget& target, std::size_t uniformCount) {
    const double activePerSeed = double(target.activeVoxelCount()) / double(std::max<std::size_t>(uniformCount, 1));
    return std::max(1, int(std::lround(std::cbrt(activePerSeed))));
}

/// What one chunk of blocks offers: its candidates for each kind of seed.
struct SeedCandidates {
    SeedCandidates(std::size_t gradientCount, std::size_t uniformCount)
        : byGradient(gradientCount), byChance(gradientCount + uniformCount) {}

    TopKeys byGradient, byChance;
    std::unordered_map<openvdb::Coord, Keyed, CoordHash> byCell;  ///< per stratum cell, its largest chance

    /// The union's candidates: the largest keys of both, and each cell's largest chance.
    void add(SeedCandidates&& other) {
        for (const Keyed& keyed : other.byGradient.take()) byGradient.offer(keyed.key, keyed.ijk);
        for (const Keyed& keyed : other.byChance.take()) byChance.offer(keyed.key, keyed.ijk);
        for (const auto& [key, keyed] : other.byCell) offerCell(key, keyed);
    }
    void offerCell(const openvdb::Coord& cell, const Keyed& keyed) {
        auto [entry, inserted] = byCell.try_emplace(cell, keyed);
        if (!inserted && keyed > entry->second) entry->second = keyed;
    }
};

/// Offers @a ijk as a gradient seed and as a chance seed; its chance key.
double offerVoxel(const openvdb::Coord& ijk, float gradient, std::mt19937_64& random, SeedCandidates& candidates) {
    std::uniform_real_distribution<double> unit(1e-300, 1.0);
    const double weight = gradient + 1e-6;
    candidates.byGradient.offer(std::log(unit(random)) / weight, ijk);
    const double chance = unit(random);
    candidates.byChance.offer(chance, ijk);
    return chance;
}

/// The largest chance in each stratum cell that one block touches, kept in a small
/// array so that the shared map is offered one entry per cell, not one per voxel
/// (a hash lookup per voxel was most of the set-up on a 45 M-voxel CT).
class BlockCells {
public:
    /// @a scratch holds the cells' entries; one vector serves every block of a chunk.
    BlockCells(const openvdb::CoordBBox& voxels, int cell, std::vector<Keyed>& scratch)
        : mCell(cell), mFirst(cellOf(voxels.min())), mBest(scratch) {
        const openvdb::Coord last = cellOf(voxels.max());
        for (int a = 0; a < 3; ++a) mCount[a] = last[a] - mFirst[a] + 1;
        mBest.assign(std::size_t(mCount[0]) * mCount[1] * mCount[2], Keyed{-1.0, openvdb::Coord()});
    }

    void offer(const openvdb::Coord& ijk, double chance) {
        const openvdb::Coord c = cellOf(ijk) - mFirst;
        Keyed& best = mBest[(std::size_t(c.z()) * mCount[1] + c.y()) * mCount[0] + c.x()];
        const Keyed keyed{chance, ijk};
        if (best.key < 0.0 || keyed > best) best = keyed;
    }

    void offerTo(SeedCandidates& candidates) const {
        for (std::size_t k = 0; k < mBest.size(); ++k) {
            if (mBest[k].key < 0.0) continue;
            candidates.offerCell(cellOf(mBest[k].ijk), mBest[k]);
        }
    }

private:
    /// Truncating division, as the cells have always been keyed.
    openvdb::Coord cellOf(const openvdb::Coord& ijk) const {
        return openvdb::Coord(ijk.x() / mCell, ijk.y() / mCell, ijk.z() / mCell);
    }

    int mCell;
    openvdb::Coord mFirst;
    int mCount[3];
    std::vector<Keyed>& mBest;
};

/// Blocks are shared out in this many chunks, each with its own random stream,
/// so that the seeds do not depend on the thread count.
constexpr std::size_t kSeedChunks = 256;

std::vector<openvdb::Coord> chooseSeeds(const VolumeTarget& target, std::size_t gradientCount, std::size_t uniformCount,
                                        std::uint64_t seed, const ProgressFn& progress) {
    const int cell = stratumSize(target, uniformCount);
    const std::vector<openvdb::Coord> blocks = blockOrigins(target.box());
    const std::size_t chunks = std::min(kSeedChunks, std::max<std::size_t>(blocks.size(), 1));
    SeedCandidates all(gradientCount, uniformCount);
    std::mutex merging;
    ProgressCounter counter(progress, chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
        SeedCandidates candidates(gradientCount, uniformCount);
        std::mt19937_64 random(streamSeed(seed, 0, chunk));
        std::vector<Keyed> cellScratch;
        for (std::size_t b = chunk * blocks.size() / chunks; b < (chunk + 1) * blocks.size() / chunks; ++b) {
            const std::bitset<kBlockVoxels> active = target.blockActive(blocks[b]);
            if (active.none()) continue;
            float gradients[kBlockVoxels];
            target.blockGradientMagnitudes(blocks[b], gradients);
            openvdb::CoordBBox voxels(blocks[b], blocks[b].offsetBy(kBlockDim - 1));
            voxels.intersect(target.box());
            BlockCells cells(voxels, cell, cellScratch);
            for (auto ijk = voxels.beginZYX(); ijk; ++ijk) {
                const int offset = blockOffset(*ijk);
                if (active[offset]) cells.offer(*ijk, offerVoxel(*ijk, gradients[offset], random, candidates));
            }
            cells.offerTo(candidates);
        }
        // Merged as each chunk ends, so that only the chunks in flight hold candidates
        // beyond the union's. Keys tie-break on coordinates: the merge order does not matter.
        std::lock_guard<std::mutex> lock(merging);
        all.add(std::move(candidates));
        counter.advance();
    });
    std::vector<openvdb::Coord> seeds = all.byGradient.takeSorted();
    std::unordered_set<openvdb::Coord, CoordHash> taken(seeds.begin(), seeds.end());
    const std::size_t wanted = gradientCount + uniformCount;
    // Cells in a random but reproducible order: by their voxel's key.
    TopKeys cells(uniformCount + gradientCount);
    for (const auto& [key, keyed] : all.byCell) cells.offer(keyed.key, keyed.ijk);
    for (TopKeys* source : {&cells, &all.byChance}) {
        for (const openvdb::Coord& ijk : source->takeSorted()) {
            if (seeds.size() == wanted) break;
            if (taken.insert(ijk).second) seeds.push_back(ijk);
        }
    }
    return seeds;
}

/// Overlapping Gaussians add up, so a colour equal to the voxel value overshoots
/// where seeds crowd and undershoots where they are sparse. One Jacobi step
/// fixes the level: divide each seed's value by the coverage (the sum of
/// opacity * exp(-q/2) over all Gaussians) at its own centre.
void balanceColours(GaussianParameters& params, const VolumeTarget& target, const std::vector<openvdb::Coord>& seeds) {
    GaussianParameters unitColour = params;
    std::fill(unitColour.values[kColours].begin(), unitColour.values[kColours].end(), 1.0f);
    unitColour.channels = params.channels;
    const GaussianField coverage(unitColour, kDefaultCutoffSigmas);
    tbb::parallel_for(std::size_t(0), seeds.size(), [&](std::size_t i) {
        std::vector<std::uint32_t> hits;
        float covered[3];
        coverage.evaluate(params.at(kMeans, i), covered, hits);
        const float own = sigmoid(*params.at(kOpacityLogits, i));
        float* colour = params.at(kColours, i);
        target.valueAt(seeds[i], colour);
        for (int c = 0; c < params.channels; ++c) colour[c] /= std::max(covered[c], own);
    });
}

/// Between seeds the coverage is lower than at them, so the balanced field still
/// runs low on average. Scale all colours by the least-squares gain
/// sum(f t) / sum(f^2) over random voxels, per channel.
void matchOverallLevel(GaussianParameters& params, const VolumeTarget& target, std::uint64_t seed) {
    const GaussianField field(params, kDefaultCutoffSigmas);
    double fieldTarget[3] = {0, 0, 0}, fieldSquared[3] = {0, 0, 0};
    std::vector<std::uint32_t> hits;
    for (const openvdb::Coord& ijk : drawUniformVoxels(target.box(), 20000, seed)) {
        float value[3], expected[3];
        const float x[3] = {float(ijk.x()), float(ijk.y()), float(ijk.z())};
        field.evaluate(x, value, hits);
        target.valueAt(ijk, expected);
        for (int c = 0; c < params.channels; ++c) {
            fieldTarget[c] += double(value[c]) * expected[c];
            fieldSquared[c] += double(value[c]) * value[c];
        }
    }
    for (int c = 0; c < params.channels; ++c) {
        if (!(fieldSquared[c] > 0.0)) continue;
        const float gain = float(std::clamp(fieldTarget[c] / fieldSquared[c], 0.1, 10.0));
        for (std::size_t i = 0; i < params.count(); ++i) params.at(kColours, i)[c] *= gain;
    }
}

}  // namespace

GaussianParameters initialiseGaussians(const VolumeTarget& target, const SeedSettings& settings,
                                       const ProgressFn& progress) {
    const std::size_t count = std::min<std::size_t>(settings.count, target.activeVoxelCount());
    const double shareSum = settings.gradientShare + settings.uniformShare;
    const double gradientFraction = shareSum > 0.0 ? settings.gradientShare / shareSum : 0.0;
    const std::size_t gradientCount = std::size_t(std::llround(gradientFraction * double(count)));
    const std::vector<openvdb::Coord> seeds =
        chooseSeeds(target, gradientCount, count - gradientCount, settings.seed, [&](double fraction) {
            if (progress) progress(0.5 * fraction);
        });
    const int stratum = stratumSize(target, count - gradientCount);
    if (progress) progress(0.5);

    std::vector<Box> points(seeds.size());
    for (std::size_t i = 0; i < seeds.size(); ++i) {
        for (int a = 0; a < 3; ++a) points[i].lower[a] = points[i].upper[a] = float(seeds[i][a]);
    }
    GaussianBvh neighbours;
    neighbours.build(points);

    GaussianParameters params(seeds.size(), target.channels());
    tbb::parallel_for(std::size_t(0), seeds.size(), [&](std::size_t i) {
        const float x[3] = {float(seeds[i].x()), float(seeds[i].y()), float(seeds[i].z())};
        std::vector<std::pair<float, std::uint32_t>> nearest;
        neighbours.nearestCentres(x, 3, std::uint32_t(i), nearest);
        float meanDistance = 1.0f;
        if (!nearest.empty()) {
            meanDistance = 0.0f;
            for (const auto& [distance, index] : nearest) meanDistance += distance / nearest.size();
        }
        // Uniform seeds keep at least half a stratum, so that together they cover
        // quiet regions even where edge seeds crowd their neighbourhood.
        const float floor = i < gradientCount ? 0.5f : 0.5f * float(stratum);
        const float sigma = std::clamp(std::max(0.5f * meanDistance, floor), 0.5f, 64.0f);
        std::copy_n(x, 3, params.at(kMeans, i));
        params.at(kRotations, i)[0] = 1.0f;
        std::fill_n(params.at(kLogScales, i), 3, std::log(sigma));
        *params.at(kOpacityLogits, i) = 0.0f;
    });
    balanceColours(params, target, seeds);
    matchOverallLevel(params, target, settings.seed);
    if (progress) progress(1.0);
    return params;
}

}  // namespace gvr
