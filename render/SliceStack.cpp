#include "SliceStack.h"

#include "Camera.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace gvr {

using openvdb::Coord;
using openvdb::Vec3d;

namespace {

/// Rounds to the nearest level (halves up; the value is never negative).
std::uint16_t quantise(float v) { return std::uint16_t(std::clamp(v, 0.0f, 1.0f) * 65535.0f + 0.5f); }

/// Any unit vector not parallel to @a normal, for the slices' in-plane axes.
Vec3d helperAxis(const Vec3d& normal) {
    return std::abs(normal.z()) < 0.9 ? Vec3d(0, 0, 1) : Vec3d(0, 1, 0);
}

/// Eight slices of samples, dense, while they are filled block by block.
struct Slab {
    int width, height;
    std::vector<StackSample> samples;  ///< [slice][row][column]
    Slab(int w, int h) : width(w), height(h), samples(std::size_t(w) * h * kBlockDim) {}
    StackSample& at(int i, int j, int k) { return samples[(std::size_t(k) * height + j) * width + i]; }
};

/// Keeps each row's runs of visible samples, joined across gaps shorter than kRunGap,
/// each between two transparent samples.
Slice compress(const Slab& slab, int k) {
    Slice slice;
    slice.rowRuns.reserve(slab.height + 1);
    const StackSample* plane = slab.samples.data() + std::size_t(k) * slab.height * slab.width;
    std::uint32_t offset = 0;
    for (int j = 0; j < slab.height; ++j) {
        slice.rowRuns.push_back(std::uint32_t(slice.runs.size()));
        const StackSample* row = plane + std::size_t(j) * slab.width;
        for (int x = 0; x < slab.width;) {
            if (row[x].a == 0) {
                ++x;
                continue;
            }
            int end = x + 1;
            for (int next = end; next < slab.width && next - end < kRunGap; ++next) {
                if (row[next].a != 0) end = next + 1;
            }
            slice.runs.push_back({std::uint32_t(x), std::uint32_t(end), offset + 1});
            offset += std::uint32_t(end - x) + 2;
            x = end;
        }
    }
    slice.rowRuns.push_back(std::uint32_t(slice.runs.size()));
    slice.samples.resize(offset);  // transparent, the padding included
    for (int j = 0; j < slab.height; ++j) {
        const StackSample* row = plane + std::size_t(j) * slab.width;
        for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r) {
            const RowRun& run = slice.runs[r];
            std::copy(row + run.begin, row + run.end, slice.samples.begin() + run.offset);
        }
    }
    return slice;
}

/// Enough samples @a step apart to cover [lo, hi], and the first one's place:
/// centred, so that samples along a volume's axis fall on its voxel centres
/// whenever the step is one voxel, and never on the faces of its cells.
std::pair<int, double> centredSamples(double lo, double hi, double step) {
    const int count = std::max(1, int(std::ceil((hi - lo) / step - 1e-9)));
    return {count, lo + 0.5 * ((hi - lo) - (count - 1) * step)};
}

/// The lattice of slices perpendicular to @a direction that covers the volume,
/// @a sliceSpacingVoxels apart (a voxel is the volume's smallest voxel edge) and
/// @a pixelMm across, but never finer than one voxel.
StackGeometry stackGeometryFor(const RenderVolume& volume, const Vec3d& direction, double sliceSpacingVoxels,
                               double pixelMm) {
    StackGeometry g;
    g.normal = direction.unit();
    g.e1 = helperAxis(g.normal).cross(g.normal).unit();
    g.e2 = g.normal.cross(g.e1).unit();
    g.pixelMm = std::max(volume.voxelMm(), pixelMm);
    g.sliceMm = volume.voxelMm() * sliceSpacingVoxels;
    Vec3d lo(1e300), hi(-1e300);
    for (const Vec3d& corner : worldCorners(volume.worldFromIndex(), volume.box())) {
        const Vec3d p(corner.dot(g.e1), corner.dot(g.e2), corner.dot(g.normal));
        lo = openvdb::math::minComponent(lo, p);
        hi = openvdb::math::maxComponent(hi, p);
    }
    const auto [width, first1] = centredSamples(lo[0], hi[0], g.pixelMm);
    const auto [height, first2] = centredSamples(lo[1], hi[1], g.pixelMm);
    const auto [slices, firstN] = centredSamples(lo[2], hi[2], g.sliceMm);
    g.width = width;
    g.height = height;
    g.slices = slices;
    g.origin = g.e1 * first1 + g.e2 * first2 + g.normal * firstN;
    return g;
}

}  // namespace

Lattice StackGeometry::lattice() const {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    const Vec3d rows[4] = {e1 * pixelMm, e2 * pixelMm, normal * sliceMm, origin};
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 3; ++c) m(r, c) = rows[r][c];
    }
    return {m, openvdb::CoordBBox(Coord(0), Coord(width - 1, height - 1, slices - 1))};
}

namespace {

/// The classified samples of all layers at one lattice voxel, combined.
struct Combined {
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

}  // namespace

SliceStack::SliceStack(const RenderVolume& volume, const Classifier& classifier, const Vec3d& direction,
                       double sliceSpacingVoxels, double pixelMm, const ProgressFn& progress)
    : SliceStack(std::vector<StackLayer>{{&volume, classifier}}, direction, sliceSpacingVoxels, pixelMm, progress) {}

SliceStack::SliceStack(const std::vector<StackLayer>& layers, const Vec3d& direction, double sliceSpacingVoxels,
                       double pixelMm, const ProgressFn& progress)
    : mGeometry(stackGeometryFor(*layers.front().volume, direction, sliceSpacingVoxels, pixelMm)),
      mSlices(mGeometry.slices) {
    const RenderVolume& volume = *layers.front().volume;
    for (Slice& slice : mSlices) slice.rowRuns.assign(mGeometry.height + 1, 0);
    std::vector<std::unique_ptr<BlockSource>> sources;
    std::set<Coord> occupied;
    for (const StackLayer& layer : layers) {
        sources.push_back(layer.volume->blocksOn(mGeometry.lattice(), layer.classifier.transferFunction().transparentUpTo()));
        for (const Coord& origin : sources.back()->occupiedBlocks()) occupied.insert(origin);
    }
    std::map<int, std::vector<Coord>> slabs;  // block origins by their first slice
    for (const Coord& origin : occupied) slabs[origin.z()].push_back(origin);
    const double lengthRatio = sliceSpacingVoxels;
    const int channels = volume.channels();
    // Nothing exists outside the volume's cells, whatever a transfer function makes
    // of the background value a source returns there.
    const openvdb::math::Mat4d volumeFromLattice = mGeometry.lattice().worldFromIndex * volume.worldFromIndex().inverse();
    const openvdb::BBoxd cells(volume.box().min().asVec3d() - Vec3d(0.5), volume.box().max().asVec3d() + Vec3d(0.5));
    ProgressCounter counter(progress, slabs.size());
    Slab slab(mGeometry.width, mGeometry.height);
    for (const auto& slabEntry : slabs) {
        // Named copies, since lambdas may not capture structured bindings in C++17.
        const int firstSlice = slabEntry.first;
        const std::vector<Coord>& origins = slabEntry.second;
        std::fill(slab.samples.begin(), slab.samples.end(), StackSample{});
        tbb::parallel_for(std::size_t(0), origins.size(), [&](std::size_t n) {
            // Per thread, not per block: this loop is the stack build's hot path.
            thread_local std::vector<float> values;
            thread_local std::vector<openvdb::CoordBBox> sampled;
            values.resize(layers.size() * kBlockVoxels * 3);
            sampled.assign(layers.size(), openvdb::CoordBBox());
            openvdb::CoordBBox voxels;
            for (std::size_t l = 0; l < layers.size(); ++l) {
                sampled[l] = sources[l]->sampleBlock(origins[n], values.data() + l * kBlockVoxels * 3);
                if (!sampled[l].empty()) voxels.expand(sampled[l]);
            }
            const bool allInside = allVoxelsInside(voxels, volumeFromLattice, cells);
            for (auto ijk = voxels.begin(); ijk; ++ijk) {
                if (!allInside && !cells.isInside(volumeFromLattice.transform((*ijk).asVec3d()))) continue;
                Combined combined;
                for (std::size_t l = 0; l < layers.size(); ++l) {
                    if (!sampled[l].isInside(*ijk)) continue;
                    const float* value = values.data() + l * kBlockVoxels * 3 + blockOffset(*ijk) * channels;
                    const std::array<float, 4> rgba = layers[l].classifier(value);
                    const float alpha = opacityOverLength(rgba[3], lengthRatio);
                    if (alpha > 0.0f) combined.add(rgba, alpha);
                }
                if (combined.layers == 0) continue;
                slab.at((*ijk).x(), (*ijk).y(), (*ijk).z() - firstSlice) = combined.sample();
            }
        });
        const int count = std::min(kBlockDim, mGeometry.slices - firstSlice);
        tbb::parallel_for(0, count, [&](int k) { mSlices[firstSlice + k] = compress(slab, k); });
        counter.advance();
    }
    for (const auto& source : sources) mGaussiansTouched += source->gaussiansReaching();
}

}  // namespace gvr
