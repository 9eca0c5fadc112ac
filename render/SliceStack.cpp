#include "render/SliceStack.h"

#include "pipeline/Error.h"
#include "pipeline/Luminance.h"
#include "render/Camera.h"
#include "render/ValueRange.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>
#include <type_traits>

namespace gvr {

using openvdb::Coord;
using openvdb::Vec3d;

namespace {

/// Rounds to the nearest level (halves up; the value is never negative).
std::uint16_t quantise(float v) { return std::uint16_t(std::clamp(v, 0.0f, 1.0f) * 65535.0f + 0.5f); }

/// Eight slices of samples, dense, while they are filled block by block.
template <typename Sample>
struct Slab {
    int width, height;
    std::vector<Sample> samples;  ///< [slice][row][column]
    Slab(int w, int h) : width(w), height(h), samples(std::size_t(w) * h * kBlockDim) {}
    Sample& at(int i, int j, int k) { return samples[(std::size_t(k) * height + j) * width + i]; }
    const Sample* plane(int k) const { return samples.data() + std::size_t(k) * height * width; }
};

/// Keeps the samples marked in @a keep (a slice's worth, row by row) in runs, joined
/// across gaps shorter than kRunGap, each between its row's neighbouring samples.
template <typename Sample>
Slice compress(const Sample* plane, int width, int height, const std::vector<std::uint8_t>& keep, Sample outside) {
    Slice slice;
    slice.rowRuns.reserve(height + 1);
    std::uint32_t offset = kStoredMargin;
    for (int j = 0; j < height; ++j) {
        slice.rowRuns.push_back(std::uint32_t(slice.runs.size()));
        const std::uint8_t* marked = keep.data() + std::size_t(j) * width;
        for (int x = 0; x < width;) {
            if (!marked[x]) {
                ++x;
                continue;
            }
            int end = x + 1;
            for (int next = end; next < width && next - end < kRunGap; ++next) {
                if (marked[next]) end = next + 1;
            }
            slice.runs.push_back({std::uint32_t(x), std::uint32_t(end), offset + 1});
            offset += std::uint32_t(end - x) + 2;
            x = end;
        }
    }
    slice.rowRuns.push_back(std::uint32_t(slice.runs.size()));
    std::vector<Sample>& stored = slice.stored<Sample>();
    stored.assign(offset + kStoredMargin, outside);
    for (int j = 0; j < height; ++j) {
        const Sample* row = plane + std::size_t(j) * width;
        for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r) {
            const RowRun& run = slice.runs[r];
            const int from = std::max(0, int(run.begin) - 1), to = std::min(width, int(run.end) + 1);
            std::copy(row + from, row + to, stored.begin() + (run.offset - run.begin + from));
        }
    }
    return slice;
}

/// The classified samples a slice keeps: the visible ones.
std::vector<std::uint8_t> visibleSamples(const StackSample* plane, int width, int height) {
    std::vector<std::uint8_t> keep(std::size_t(width) * height);
    for (std::size_t n = 0; n < keep.size(); ++n) keep[n] = plane[n].a != 0;
    return keep;
}

/// The classified samples of all layers at one lattice voxel, combined.
struct LayerBlend {
    float keep = 1.0f, r = 0.0f, g = 0.0f, b = 0.0f, alphaSum = 0.0f, single = 0.0f;
    int layers = 0;

    void add(const std::array<float, 4>& rgba, float alpha) {
        keep *= 1.0f - alpha;
        r += rgba[0] * alpha;
        g += rgba[1] * alpha;
        b += rgba[2] * alpha;
        alphaSum += alpha;
        single = alpha;
        ++layers;
    }

    StackSample sample() const {
        // One layer keeps its own numbers exactly; 1 - (1 - alpha) would round.
        const float alpha = layers == 1 ? single : 1.0f - keep;
        const float scale = layers == 1 ? 1.0f : alpha / alphaSum;
        return {quantise(r * scale), quantise(g * scale), quantise(b * scale), quantise(alpha)};
    }
};

/// The volume's cells, seen from the stack's lattice: nothing exists outside them,
/// whatever a transfer function makes of the background value a source returns there.
class VolumeCells {
public:
    VolumeCells(const StackGeometry& g, const RenderVolume& volume)
        : mVolumeFromLattice(g.lattice().worldFromIndex * volume.worldFromIndex().inverse()),
          mCells(volume.box().min().asVec3d() - Vec3d(0.5), volume.box().max().asVec3d() + Vec3d(0.5)) {}

    /// Calls @a visit for each lattice voxel of @a voxels inside the cells.
    template <typename Visit>
    void forEachInside(const openvdb::CoordBBox& voxels, Visit visit) const {
        if (voxels.empty()) return;
        const bool allInside = allVoxelsInside(voxels, mVolumeFromLattice, mCells);
        for (auto ijk = voxels.begin(); ijk; ++ijk) {
            if (allInside || mCells.isInside(mVolumeFromLattice.transform((*ijk).asVec3d()))) visit(*ijk);
        }
    }

private:
    openvdb::math::Mat4d mVolumeFromLattice;
    openvdb::BBoxd mCells;
};

/// A colour volume's sample while its slab fills: the colour it is drawn in, and
/// the luminance that classifies it.
struct ColourValue {
    std::array<float, 3> colour{};
    float luminance = 0.0f;
};

/// @a value (as many floats as the volume has channels) as a slab keeps it: the
/// value, or the colour and its luminance (the last argument picks which).
float slabValue(const float* value, const Classifier&, float) { return *value; }
ColourValue slabValue(const float* value, const Classifier& classifier, ColourValue) {
    return {classifier.colour(value), float(luminance(value))};
}

/// What classifies a slab's sample: its value, or its luminance.
float slabKey(float value) { return value; }
float slabKey(const ColourValue& value) { return value.luminance; }

/// A slab's sample as the slice keeps it, its key as @a code: the code, or the colour
/// and the code.
std::uint16_t storedOf(float, std::uint16_t code) { return code; }
StackSample storedOf(const ColourValue& value, std::uint16_t code) {
    return {quantise(value.colour[0]), quantise(value.colour[1]), quantise(value.colour[2]), code};
}

/// Writes the values of the block at @a origin into @a slab (whose first slice is
/// @a firstSlice), as @a classifier's volume has them.
template <typename Value>
void storeValues(const BlockSource& source, const Classifier& classifier, const VolumeCells& cells, const Coord& origin,
                 int firstSlice, Slab<Value>& slab) {
    thread_local std::vector<float> values;  // per thread, not per block: the build's hot path
    const int channels = classifier.channels();
    values.resize(std::size_t(kBlockVoxels) * channels);
    cells.forEachInside(source.sampleBlock(origin, values.data()), [&](const Coord& ijk) {
        slab.at(ijk.x(), ijk.y(), ijk.z() - firstSlice) =
            slabValue(values.data() + blockOffset(ijk) * channels, classifier, Value{});
    });
}

/// Writes the block at @a origin into @a slab classified: each layer's colour and
/// opacity over one slice spacing, the layers combined where they meet.
void storeClassified(const std::vector<StackLayer>& layers, const std::vector<std::unique_ptr<BlockSource>>& sources,
                     double sliceSpacingVoxels, const VolumeCells& cells, const Coord& origin, int firstSlice,
                     Slab<StackSample>& slab) {
    // Per thread, not per block: this is the build's hot path.
    thread_local std::vector<float> values;
    thread_local std::vector<openvdb::CoordBBox> sampled;
    values.resize(layers.size() * kBlockVoxels * 3);
    sampled.assign(layers.size(), openvdb::CoordBBox());
    openvdb::CoordBBox voxels;
    for (std::size_t l = 0; l < layers.size(); ++l) {
        sampled[l] = sources[l]->sampleBlock(origin, values.data() + l * kBlockVoxels * 3);
        if (!sampled[l].empty()) voxels.expand(sampled[l]);
    }
    const int channels = layers.front().volume->channels();
    cells.forEachInside(voxels, [&](const Coord& ijk) {
        LayerBlend combined;
        for (std::size_t l = 0; l < layers.size(); ++l) {
            if (!sampled[l].isInside(ijk)) continue;
            const float* value = values.data() + l * kBlockVoxels * 3 + blockOffset(ijk) * channels;
            const std::array<float, 4> rgba = layers[l].classifier(value);
            const float alpha = opacityOverLength(rgba[3], sliceSpacingVoxels);
            if (alpha > 0.0f) combined.add(rgba, alpha);
        }
        if (combined.layers > 0) slab.at(ijk.x(), ijk.y(), ijk.z() - firstSlice) = combined.sample();
    });
}

/// Fills the slices slab by slab: @a storeBlock writes one block's samples into a
/// slab of eight slices (in parallel over blocks), then @a compressSlab makes
/// slices of it. Throws Cancelled before a slab once @a cancel is set.
template <typename Sample, typename StoreBlock, typename CompressSlab>
void buildSlices(const StackGeometry& g, const std::map<int, std::vector<Coord>>& slabs, Sample outside,
                 ProgressCounter& counter, const std::atomic<bool>* cancel, StoreBlock storeBlock,
                 CompressSlab compressSlab) {
    Slab<Sample> slab(g.width, g.height);
    for (const auto& slabEntry : slabs) {
        if (cancel && cancel->load()) throw Cancelled("slice stack build");
        // Named copies, since lambdas may not capture structured bindings in C++17.
        const int firstSlice = slabEntry.first;
        const std::vector<Coord>& origins = slabEntry.second;
        std::fill(slab.samples.begin(), slab.samples.end(), outside);
        tbb::parallel_for(std::size_t(0), origins.size(),
                          [&](std::size_t n) { storeBlock(origins[n], firstSlice, slab); });
        compressSlab(firstSlice, std::min(kBlockDim, g.slices - firstSlice), slab);
        counter.advance();
    }
}

/// The levels each cell of a slice of values spans (a cell: two samples of two
/// neighbouring rows, since resampling may give any value between its corners),
/// kept at the cell's first corner. Beyond the last row and column, cells are
/// empty: lo > hi.
struct CellLevels {
    std::vector<std::uint16_t> lo, hi;
};

// The loops of a plane of values run in eight lanes where the processor has AVX2
// (target_clones picks at load time): a stack build codes and judges every sample.

/// @a size values in @a coding's codes.
__attribute__((target_clones("avx2", "default"))) void codeValues(const float* values, std::size_t size,
                                                                  const ValueCoding& coding, std::uint16_t* codes) {
    for (std::size_t n = 0; n < size; ++n) codes[n] = coding.code(values[n]);
}

/// The nearest level of each of @a size codes.
__attribute__((target_clones("avx2", "default"))) void levelsOfCodes(const std::uint16_t* codes, std::size_t size,
                                                                     const ValueCoding& coding, std::uint16_t* levels) {
    for (std::size_t n = 0; n < size; ++n) levels[n] = std::uint16_t(ValueLevels::nearest(coding.level(codes[n])));
}

/// The least and greatest of each cell's four corner levels, a row of cells at a time.
__attribute__((target_clones("avx2", "default"))) void cellRow(const std::uint16_t* upper, const std::uint16_t* lower,
                                                               int cells, std::uint16_t* lo, std::uint16_t* hi) {
    for (int x = 0; x < cells; ++x) {
        lo[x] = std::min(std::min(upper[x], upper[x + 1]), std::min(lower[x], lower[x + 1]));
        hi[x] = std::max(std::max(upper[x], upper[x + 1]), std::max(lower[x], lower[x + 1]));
    }
}

CellLevels cellLevels(const std::vector<std::uint16_t>& codes, const ValueCoding& coding, int width, int height) {
    const std::size_t size = std::size_t(width) * height;
    std::vector<std::uint16_t> sampleLevels(size);
    levelsOfCodes(codes.data(), size, coding, sampleLevels.data());
    CellLevels cells{std::vector<std::uint16_t>(size, ValueLevels::kCount - 1), std::vector<std::uint16_t>(size, 0)};
    for (int j = 0; j + 1 < height; ++j) {
        const std::size_t row = std::size_t(j) * width;
        cellRow(sampleLevels.data() + row, sampleLevels.data() + row + width, width - 1, cells.lo.data() + row,
                cells.hi.data() + row);
    }
    return cells;
}

/// Widens cells [to, to + count) of @a into by the levels of cells [from, from + count) of @a cells.
void takeLevels(CellLevels& into, std::size_t to, const CellLevels& cells, std::size_t from, std::size_t count) {
    for (std::size_t n = 0; n < count; ++n) {
        into.lo[to + n] = std::min(into.lo[to + n], cells.lo[from + n]);
        into.hi[to + n] = std::max(into.hi[to + n], cells.hi[from + n]);
    }
}

/// Each cell takes the levels of every cell within @a reach of it, across and down:
/// what a ray through it may meet in a neighbouring slice, sheared by up to @a reach.
/// Shift by shift, so that each pass runs along memory.
CellLevels widened(const CellLevels& cells, int width, int height, int reach) {
    CellLevels across = cells;
    for (int d = 1; d <= std::min(reach, width - 1); ++d) {
        for (int j = 0; j < height; ++j) {
            const std::size_t row = std::size_t(j) * width;
            takeLevels(across, row, cells, row + d, width - d);
            takeLevels(across, row + d, cells, row, width - d);
        }
    }
    CellLevels both = across;
    for (int d = 1; d <= std::min(reach, height - 1); ++d) {
        const std::size_t rows = std::size_t(height - d) * width, shift = std::size_t(d) * width;
        takeLevels(both, 0, across, shift, rows);
        takeLevels(both, shift, across, 0, rows);
    }
    return both;
}

/// The samples at the corners of the marked cells (a cell is kept at its first corner,
/// as CellLevels): a pass along memory instead of four scattered marks a cell.
std::vector<std::uint8_t> cornersOf(const std::vector<std::uint8_t>& cells, int width, int height) {
    std::vector<std::uint8_t> corners(cells.size());
    for (int j = 0; j < height; ++j) {
        std::uint8_t* row = corners.data() + std::size_t(j) * width;
        const std::uint8_t* cellRow = cells.data() + std::size_t(j) * width;
        row[0] = cellRow[0];
        for (int x = 1; x < width; ++x) row[x] = cellRow[x] | cellRow[x - 1];
    }
    for (int j = height - 1; j > 0; --j) {
        std::uint8_t* row = corners.data() + std::size_t(j) * width;
        const std::uint8_t* above = row - width;
        for (int x = 0; x < width; ++x) row[x] |= above[x];
    }
    return corners;
}

/// Compresses slices of values (float or ColourValue) into codes as their slabs are
/// sampled, keeping the corners of every cell some of whose values could be seen.
/// For segments, a cell is judged with what a ray through it meets in the
/// neighbouring slices, so each slab's last slice waits for the next slab.
template <typename Value>
class ValueSliceKeeper {
public:
    ValueSliceKeeper(const StackGeometry& g, const ValueLevels& levels, std::optional<int> segmentReach, Value outside,
                     std::vector<Slice>& slices)
        : mGeometry(g), mLevels(levels), mReach(segmentReach), mOutside(outside), mSlices(slices) {}

    void addSlab(int firstSlice, int count, const Slab<Value>& slab) {
        std::vector<Plane> planes(count);
        tbb::parallel_for(0, count, [&](int k) { planes[k] = plane(firstSlice + k, slab.plane(k)); });
        if (!mReach) {
            tbb::parallel_for(0, count, [&](int k) { compressSlice(planes[k], nullptr, nullptr); });
            return;
        }
        std::vector<const Plane*> order;  // consecutive planes, perhaps with gaps between
        if (mBefore) order.push_back(&*mBefore);
        if (mWaiting) order.push_back(&*mWaiting);
        for (const Plane& p : planes) order.push_back(&p);
        const std::size_t from = mBefore ? 1 : 0, last = order.size() - 1;
        tbb::parallel_for(
            from, last, [&](std::size_t n) { compressSlice(*order[n], n > 0 ? order[n - 1] : nullptr, order[n + 1]); });
        std::optional<Plane> before;
        if (last > 0) {
            // Compressed already, but its cells still judge the slice after it.
            before = Plane{order[last - 1]->slice, {}, {}, {}, order[last - 1]->reachable};
        }
        mBefore = std::move(before);
        mWaiting = *order[last];
    }

    /// Compresses the slice still waiting for its neighbour.
    void finish() {
        if (mWaiting) compressSlice(*mWaiting, mBefore ? &*mBefore : nullptr, nullptr);
    }

private:
    using Stored = decltype(storedOf(Value{}, 0));

    struct Plane {
        int slice = 0;
        ValueCoding coding;
        std::vector<Stored> stored;
        CellLevels cells, reachable;  ///< reachable: widened by the reach, for the neighbouring slices
    };

    /// The keys of @a size values: @a values themselves when they are floats.
    static const float* keysOf(const float* values, std::size_t, std::vector<float>&) { return values; }
    static const float* keysOf(const ColourValue* values, std::size_t size, std::vector<float>& keys) {
        keys.resize(size);
        for (std::size_t n = 0; n < size; ++n) keys[n] = values[n].luminance;
        return keys.data();
    }

    /// Slice @a slice's @a values as stored, and the levels of its cells. The codes
    /// span the keys, the outside's too, which pads the runs.
    Plane plane(int slice, const Value* values) const {
        const std::size_t size = std::size_t(mGeometry.width) * mGeometry.height;
        std::vector<float> scratch;
        const float* keys = keysOf(values, size, scratch);
        const auto [lo, hi] = valueRange(keys, size);
        const float outside = slabKey(mOutside);
        Plane p{slice, mLevels.codingFor(std::min(lo, outside), std::max(hi, outside)), {}, {}, {}};
        std::vector<std::uint16_t> codes(size);
        codeValues(keys, size, p.coding, codes.data());
        p.cells = cellLevels(codes, p.coding, mGeometry.width, mGeometry.height);
        if (mReach) p.reachable = widened(p.cells, mGeometry.width, mGeometry.height, *mReach);
        if constexpr (std::is_same_v<Stored, std::uint16_t>) {
            p.stored = std::move(codes);
        } else {
            p.stored.resize(size);
            for (std::size_t n = 0; n < size; ++n) p.stored[n] = storedOf(values[n], codes[n]);
        }
        return p;
    }

    /// Compresses @a p, judging its cells with @a before's and @a after's reachable
    /// levels where those are the slices next to it.
    void compressSlice(const Plane& p, const Plane* before, const Plane* after) const {
        const int width = mGeometry.width, height = mGeometry.height;
        if (before && before->slice != p.slice - 1) before = nullptr;
        if (after && after->slice != p.slice + 1) after = nullptr;
        const std::size_t size = std::size_t(width) * height;
        // A segment's cell is judged with what rays through it meet in the neighbouring slices.
        CellLevels withNeighbours;
        const CellLevels* judged = &p.cells;
        if (before || after) {
            withNeighbours = p.cells;
            for (const Plane* neighbour : {before, after}) {
                if (neighbour) takeLevels(withNeighbours, 0, neighbour->reachable, 0, size);
            }
            judged = &withNeighbours;
        }
        std::vector<std::uint8_t> seen(size);
        mLevels.markVisible(judged->lo.data(), judged->hi.data(), size, seen.data());
        // The last column and row hold no cells (a cell is kept at its first corner),
        // whatever the neighbours' widened levels say there.
        for (int j = 0; j < height; ++j) seen[std::size_t(j) * width + width - 1] = 0;
        if (height > 0) std::fill(seen.end() - width, seen.end(), 0);
        mSlices[p.slice] = compress(p.stored.data(), width, height, cornersOf(seen, width, height),
                                    storedOf(mOutside, p.coding.code(slabKey(mOutside))));
        mSlices[p.slice].coding = p.coding;
    }

    const StackGeometry& mGeometry;
    const ValueLevels& mLevels;
    std::optional<int> mReach;
    Value mOutside;
    std::vector<Slice>& mSlices;
    std::optional<Plane> mBefore, mWaiting;  ///< the last two planes of the slabs so far
};

/// Whether a stack of @a layers may keep values, classified as they are composited,
/// or must keep classified samples: values for one layer. Values outside the volume
/// are not the background's but nothing at all; a visible background keeps the
/// samples classified, so that they stay nothing.
StackContent contentOf(const std::vector<StackLayer>& layers) {
    const RenderVolume& volume = *layers.front().volume;
    if (layers.size() > 1 || layers.front().classifier.transferFunction()(volume.backgroundKey())[3] != 0.0f) {
        return StackContent::Classified;
    }
    return volume.channels() == 1 ? StackContent::Values : StackContent::Colours;
}

/// A stack's lattice and what its slices hold. Stacks of values take the voxel
/// centres nearby. A colour volume keeps its colours only on them, where their
/// resampling is the trilinear field's: elsewhere colour and opacity, resampled
/// apart, lose how they vary together (dark tissue opaque, pale tissue clear), and
/// images of a colour section came out paler than the ray marcher's, further from
/// it than classified samples (docs/benchmarks.md, "Stacks of colours").
std::pair<StackGeometry, StackContent> layoutFor(const std::vector<StackLayer>& layers, const Vec3d& direction,
                                                 double sliceSpacingVoxels, double sampleMm, StackSampling sampling) {
    const RenderVolume& volume = *layers.front().volume;
    const StackContent content = contentOf(layers);
    const bool fine = sampling == StackSampling::Voxels;
    const StackGeometry g =
        stackGeometryFor(volume, direction, sliceSpacingVoxels, sampleMm, content != StackContent::Classified, fine);
    if (content == StackContent::Colours && !g.samplesOnVoxels) {
        return {stackGeometryFor(volume, direction, sliceSpacingVoxels, sampleMm, false, fine),
                StackContent::Classified};
    }
    return {g, content};
}

}  // namespace

SliceStack::SliceStack(const RenderVolume& volume, const Classifier& classifier, const Vec3d& direction,
                       double sliceSpacingVoxels, double sampleMm, const ProgressFn& progress,
                       const std::atomic<bool>* cancel, StackSampling sampling, SegmentViews segments)
    : SliceStack(std::vector<StackLayer>{{&volume, classifier}}, direction, sliceSpacingVoxels, sampleMm, progress,
                 cancel, sampling, segments) {}

SliceStack::SliceStack(const std::vector<StackLayer>& layers, const Vec3d& direction, double sliceSpacingVoxels,
                       double sampleMm, const ProgressFn& progress, const std::atomic<bool>* cancel,
                       StackSampling sampling, SegmentViews segments) {
    std::tie(mGeometry, mContent) = layoutFor(layers, direction, sliceSpacingVoxels, sampleMm, sampling);
    mSlices.resize(mGeometry.slices);
    const RenderVolume& volume = *layers.front().volume;
    const Classifier& classifier = layers.front().classifier;
    if (mContent != StackContent::Classified) {
        mLevels = std::make_unique<ValueLevels>(classifier.transferFunction(), mGeometry.sliceVoxels);
    }
    // Pre-integration takes one value a sample.
    if (mContent == StackContent::Values) mClassification = segments.classification;
    for (Slice& slice : mSlices) slice.rowRuns.assign(mGeometry.height + 1, 0);
    std::vector<std::unique_ptr<BlockSource>> sources;
    std::vector<Coord> occupied;
    for (const StackLayer& layer : layers) {
        const double invisibleUpTo = layer.classifier.transferFunction().transparentUpTo();
        const Lattice lattice = mGeometry.lattice();
        sources.push_back(sampling == StackSampling::Preview ? layer.volume->previewBlocksOn(lattice, invisibleUpTo)
                                                             : layer.volume->blocksOn(lattice, invisibleUpTo));
        const std::vector<Coord> blocks = sources.back()->occupiedBlocks();
        occupied.insert(occupied.end(), blocks.begin(), blocks.end());
    }
    std::sort(occupied.begin(), occupied.end());
    occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
    std::map<int, std::vector<Coord>> slabs;  // block origins by their first slice
    for (const Coord& origin : occupied) slabs[origin.z()].push_back(origin);
    const VolumeCells cells(mGeometry, volume);
    ProgressCounter counter(progress, slabs.size());
    // Built alike for either kind of value: the slab's sample, and what lies outside.
    const auto buildValues = [&](const auto outside) {
        using Value = std::decay_t<decltype(outside)>;
        std::optional<int> reach;
        if (mClassification == Classification::Segments) reach = segmentReach(mGeometry, segments.maxAngleDeg);
        ValueSliceKeeper<Value> keeper(mGeometry, *mLevels, reach, outside, mSlices);
        buildSlices(
            mGeometry, slabs, outside, counter, cancel,
            [&](const Coord& origin, int firstSlice, Slab<Value>& slab) {
                storeValues(*sources.front(), classifier, cells, origin, firstSlice, slab);
            },
            [&](int firstSlice, int count, const Slab<Value>& slab) { keeper.addSlab(firstSlice, count, slab); });
        keeper.finish();
    };
    if (mContent == StackContent::Values) {
        buildValues(float(volume.backgroundKey()));
    } else if (mContent == StackContent::Colours) {
        buildValues(slabValue(volume.background().data(), classifier, ColourValue{}));
    } else {
        buildSlices(
            mGeometry, slabs, StackSample{}, counter, cancel,
            [&](const Coord& origin, int firstSlice, Slab<StackSample>& slab) {
                storeClassified(layers, sources, mGeometry.sliceVoxels, cells, origin, firstSlice, slab);
            },
            [&](int firstSlice, int count, const Slab<StackSample>& slab) {
                tbb::parallel_for(0, count, [&](int k) {
                    mSlices[firstSlice + k] =
                        compress(slab.plane(k), mGeometry.width, mGeometry.height,
                                 visibleSamples(slab.plane(k), mGeometry.width, mGeometry.height), StackSample{});
                });
            });
    }
    for (const auto& source : sources) mGaussiansTouched += source->gaussiansReaching();
}

}  // namespace gvr
