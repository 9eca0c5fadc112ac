#include "render/RenderVolume.h"

#include "pipeline/Error.h"
#include "pipeline/FieldToGrid.h"
#include "pipeline/FloatVolume.h"
#include "pipeline/Luminance.h"
#include "pipeline/VolumeBorder.h"
#include "pipeline/VolumeGrid.h"
#include "pipeline/VolumeMetadata.h"
#include "render/ValueRange.h"
#include "render/VoxelBrick.h"

#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace gvr {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::math::Mat4d;

namespace {

/// Enough values for stable percentiles.
constexpr std::size_t kStatisticsSamples = 50000;

float keyOf(const float* value, int channels) { return channels == 1 ? value[0] : float(luminance(value)); }

/// The Gaussians themselves at a lattice's points, for previews.
class GaussianBlocks : public BlockSource {
public:
    /// @param skipUpTo  blocks whose field cannot exceed this (normalised) stay empty
    /// @param everyBlock  the background is visible: unreached blocks count too
    GaussianBlocks(const GaussianField& field, const Mat4d& worldFromIndex, const Lattice& lattice,
                   const CoordBBox& fieldBox, const ValueMapping& mapping, float skipUpTo, bool everyBlock)
        : mSampler(field, worldFromIndex, lattice, fieldBox),
          mMapping(mapping),
          mSkipUpTo(skipUpTo),
          mEveryBlock(everyBlock) {}

    std::vector<Coord> occupiedBlocks() const override {
        return mEveryBlock ? blockOrigins(mSampler.lattice().box) : mSampler.occupiedBlocks();
    }
    std::size_t gaussiansReaching() const override { return mSampler.reachingGaussians(); }

    CoordBBox sampleBlock(const Coord& origin, float* values) const override {
        const int channels = mSampler.channels();
        std::fill(values, values + kBlockVoxels * channels, 0.0f);
        const CoordBBox voxels = mSampler.sampleBlock(origin, values, mSkipUpTo, BlockEvaluation::Rows);
        for (int n = 0; n < kBlockVoxels * channels; ++n) {
            values[n] = mMapping.toPhysicalFloat(values[n], n % channels);
        }
        return voxels;
    }

private:
    LatticeSampler mSampler;
    ValueMapping mMapping;
    float mSkipUpTo;
    bool mEveryBlock;
};

/// The key of a grid value: the value, or its luminance.
double keyOf(float value) { return value; }
double keyOf(const openvdb::Vec3s& value) { return luminance(value); }

/// The leaf-sized cell that holds @a voxel: floor division, negative voxels included.
Coord cellOf(const Coord& voxel) {
    const auto floorDiv = [](int v) { return v >= 0 ? v / kBlockDim : -((kBlockDim - 1 - v) / kBlockDim); };
    return Coord(floorDiv(voxel.x()), floorDiv(voxel.y()), floorDiv(voxel.z()));
}

/// The highest value in a leaf, active or not: a pass along its array, where its
/// value iterator made the ceilings of a chest CT most of a coarse build.
float ceilingOf(const openvdb::FloatTree::LeafNodeType& leaf) {
    return valueRange(leaf.buffer().data(), openvdb::FloatTree::LeafNodeType::SIZE).second;
}

/// The highest luminance in a leaf, active or not.
float ceilingOf(const openvdb::Vec3STree::LeafNodeType& leaf) {
    const openvdb::Vec3s* values = leaf.buffer().data();
    float ceiling = -INFINITY;
    for (openvdb::Index n = 0; n < openvdb::Vec3STree::LeafNodeType::SIZE; ++n) {
        ceiling = std::max(ceiling, float(keyOf(values[n])));
    }
    return ceiling;
}

/// The highest key (value, or luminance) in each leaf-sized cell of a grid's box,
/// inactive voxels and tiles included: the most a trilinear sample there can reach,
/// so that a stack need not sample where nothing could be seen.
template <typename GridT>
class CellCeilings {
public:
    CellCeilings(const GridT& grid, const CoordBBox& box) {
        if (box.empty()) return;
        mFirst = cellOf(box.min());
        mCount = cellOf(box.max()) - mFirst + Coord(1);
        mCeilings.resize(std::size_t(mCount.x()) * mCount.y() * mCount.z());
        tbb::parallel_for(0, mCount.x(), [&](int i) {
            const auto accessor = grid.getConstAccessor();
            for (int j = 0; j < mCount.y(); ++j) {
                for (int k = 0; k < mCount.z(); ++k) {
                    const Coord cell = mFirst + Coord(i, j, k);
                    const Coord origin(cell.x() * kBlockDim, cell.y() * kBlockDim, cell.z() * kBlockDim);
                    float ceiling = -INFINITY;
                    if (const auto* leaf = accessor.probeConstLeaf(origin)) {
                        ceiling = ceilingOf(*leaf);
                    } else {
                        ceiling = float(keyOf(accessor.getValue(origin)));  // a tile, or the background
                    }
                    mCeilings[index(Coord(i, j, k))] = ceiling;
                }
            }
        });
    }

    /// Whether some voxel of @a voxels inside the box holds a key above @a level.
    bool anyAbove(const CoordBBox& voxels, float level) const {
        const Coord lo = Coord::maxComponent(cellOf(voxels.min()) - mFirst, Coord(0));
        const Coord hi = Coord::minComponent(cellOf(voxels.max()) - mFirst, mCount - Coord(1));
        for (int i = lo.x(); i <= hi.x(); ++i) {
            for (int j = lo.y(); j <= hi.y(); ++j) {
                for (int k = lo.z(); k <= hi.z(); ++k) {
                    if (mCeilings[index(Coord(i, j, k))] > level) return true;
                }
            }
        }
        return false;
    }

private:
    std::size_t index(const Coord& cell) const {
        return (std::size_t(cell.x()) * mCount.y() + cell.y()) * mCount.z() + cell.z();
    }

    Coord mFirst, mCount;
    std::vector<float> mCeilings;
};

/// The most voxels a block's brick may hold per sample it serves.
constexpr std::uint64_t kBrickVoxelsPerSample = 32;

template <typename GridT>
class GridBlocks : public BlockSource {
public:
    /// @param invisibleUpTo  keys up to this are transparent: blocks whose samples
    ///                       cannot exceed it are not sampled, unless the background
    ///                       is visible (then every block counts)
    /// @param gaussiansEvaluated  what gaussiansReaching() reports: the Gaussians
    ///                            evaluated to make the grid for this build, if any
    GridBlocks(const GridT& grid, const Lattice& lattice, double invisibleUpTo, bool backgroundVisible,
               std::size_t gaussiansEvaluated)
        : mGrid(grid),
          mLattice(lattice),
          mInvisibleUpTo(invisibleUpTo),
          mEveryBlock(backgroundVisible),
          mGaussiansEvaluated(gaussiansEvaluated),
          mGridFromLattice(lattice.worldFromIndex * grid.transform().baseMap()->getAffineMap()->getMat4().inverse()),
          mActive(grid.evalActiveVoxelBoundingBox().expandBy(1)),  // trilinear samples reach one voxel out
          mCeilings(grid, mEveryBlock ? CoordBBox() : mActive),
          mGridAxisOf(gridAxesOf(mGridFromLattice)) {}

    std::vector<Coord> occupiedBlocks() const override {
        std::vector<Coord> origins = blockOrigins(mLattice.box);
        if (mEveryBlock) return origins;
        origins.erase(std::remove_if(origins.begin(), origins.end(), [&](const Coord& o) { return !mayBeSeen(o); }),
                      origins.end());
        return origins;
    }

    std::size_t gaussiansReaching() const override { return mGaussiansEvaluated; }

    CoordBBox sampleBlock(const Coord& origin, float* values) const override {
        CoordBBox voxels(origin, origin + Coord(kBlockDim - 1));
        voxels.intersect(mLattice.box);
        if (voxels.empty()) return voxels;
        const openvdb::BBoxd reach = gridBoxOf(voxels);
        // A voxel more on each side: a sample's position may round past the corners'.
        const CoordBBox corners(Coord::floor(reach.min()) - Coord(1), Coord::floor(reach.max()) + Coord(2));
        constexpr int channels = std::is_same_v<typename GridT::ValueType, openvdb::Vec3s> ? 3 : 1;
        const auto sampleEach = [&](const auto& trilinear) {
            // Mat4d::transform's sums, in its order, with the terms a row of voxels shares
            // added once: the same positions to the bit.
            const Mat4d& m = mGridFromLattice;
            for (int i = voxels.min().x(); i <= voxels.max().x(); ++i) {
                for (int j = voxels.min().y(); j <= voxels.max().y(); ++j) {
                    const double di = i, dj = j;
                    const double rowX = di * m(0, 0) + dj * m(1, 0), rowY = di * m(0, 1) + dj * m(1, 1),
                                 rowZ = di * m(0, 2) + dj * m(1, 2);
                    for (int k = voxels.min().z(); k <= voxels.max().z(); ++k) {
                        const double dk = k;
                        const openvdb::Vec3d x(rowX + dk * m(2, 0) + m(3, 0), rowY + dk * m(2, 1) + m(3, 1),
                                               rowZ + dk * m(2, 2) + m(3, 2));
                        trilinear(x, values + blockOffset(Coord(i, j, k)) * channels);
                    }
                }
            }
        };
        const auto accessor = mGrid.getConstAccessor();
        // Copying a voxel costs a small part of a sample through the tree, so a brick
        // pays even for a lattice a few times coarser than the voxels (a preview's
        // is twice as coarse); far coarser, a block reads few of its voxels.
        if (corners.volume() > kBrickVoxelsPerSample * voxels.volume()) {
            sampleEach([&](const openvdb::Vec3d& x, float* out) { GridRenderVolume::trilinear(accessor, x, out); });
            return voxels;
        }
        thread_local VoxelBrick<GridT> brick;  // per thread, not per block: the build's hot path
        brick.fill(mGrid, corners);
        if (mGridAxisOf) {
            sampleAlongAxes(brick, voxels, values);
        } else {
            sampleEach([&](const openvdb::Vec3d& x, float* out) { brick.trilinear(x, out); });
        }
        return voxels;
    }

private:
    /// The grid axis each lattice axis runs along, when each runs along one (axis
    /// stacks, and the grids' own lattices): no other axis adds to its coordinate.
    static std::optional<std::array<int, 3>> gridAxesOf(const Mat4d& gridFromLattice) {
        std::array<int, 3> axisOf{};
        int seen = 0;
        for (int r = 0; r < 3; ++r) {
            int nonZero = 0;
            for (int c = 0; c < 3; ++c) {
                if (gridFromLattice(r, c) != 0.0) {
                    ++nonZero;
                    axisOf[r] = c;
                }
            }
            if (nonZero != 1) return std::nullopt;
            seen |= 1 << axisOf[r];
        }
        if (seen != 7) return std::nullopt;
        return axisOf;
    }

    /// As the general loop, to the bit (the terms a lattice axis leaves out are
    /// exact zeros): each voxel's place along each axis found once for the block,
    /// and the brick blended axis by axis.
    template <typename Brick>
    void sampleAlongAxes(const Brick& brick, const CoordBBox& voxels, float* values) const {
        constexpr int channels = std::is_same_v<typename GridT::ValueType, openvdb::Vec3s> ? 3 : 1;
        const std::array<int, 3>& axisOf = *mGridAxisOf;
        std::array<typename Brick::Steps, 3> alongGrid;  // by grid axis
        for (int r = 0; r < 3; ++r) {
            const int c = axisOf[r];
            typename Brick::Steps& steps = alongGrid[c];
            steps.count = voxels.dim()[r];
            for (int n = 0; n < steps.count; ++n) {
                const double x = double(voxels.min()[r] + n) * mGridFromLattice(r, c) + mGridFromLattice(3, c);
                steps.base[n] = int(std::floor(x));
                steps.t[n] = x - double(steps.base[n]);
            }
        }
        brick.trilinearAlongAxes(alongGrid[0], alongGrid[1], alongGrid[2], [&](int a, int b, int c) {
            const std::array<int, 3> along{a, b, c};  // by grid axis
            const Coord ijk = voxels.min() + Coord(along[axisOf[0]], along[axisOf[1]], along[axisOf[2]]);
            return values + blockOffset(ijk) * channels;
        });
    }

    /// The box, in the grid's index space, that lattice voxels @a voxels span.
    openvdb::BBoxd gridBoxOf(const CoordBBox& voxels) const {
        openvdb::Vec3d lo(1e300), hi(-1e300);
        for (int c = 0; c < 8; ++c) {
            const Coord corner(c & 1 ? voxels.max().x() : voxels.min().x(), c & 2 ? voxels.max().y() : voxels.min().y(),
                               c & 4 ? voxels.max().z() : voxels.min().z());
            const openvdb::Vec3d p = mGridFromLattice.transform(corner.asVec3d());
            lo = openvdb::math::minComponent(lo, p);
            hi = openvdb::math::maxComponent(hi, p);
        }
        return {lo, hi};
    }

    /// Whether the block's samples, or their neighbours on the lattice, reach a voxel
    /// that is active and could be seen: compositing resamples between neighbours,
    /// and a block left out holds the background instead of its values.
    bool mayBeSeen(const Coord& origin) const {
        const openvdb::BBoxd reach = gridBoxOf(CoordBBox(origin - Coord(1), origin + Coord(kBlockDim)));
        if (mActive.empty()) return false;
        for (int a = 0; a < 3; ++a) {
            if (reach.max()[a] < mActive.min()[a] || reach.min()[a] > mActive.max()[a]) return false;
        }
        // The voxels the samples' trilinear corners read.
        const CoordBBox corners(Coord::floor(reach.min()), Coord::floor(reach.max()) + Coord(1));
        return mCeilings.anyAbove(corners, float(mInvisibleUpTo));
    }

    const GridT& mGrid;
    Lattice mLattice;
    double mInvisibleUpTo;
    bool mEveryBlock;
    std::size_t mGaussiansEvaluated;
    Mat4d mGridFromLattice;
    CoordBBox mActive;
    CellCeilings<GridT> mCeilings;
    std::optional<std::array<int, 3>> mGridAxisOf;  ///< by lattice axis, when each runs along one
};

/// Trilinear samples of a float or Vec3s @a grid on @a lattice (see GridBlocks).
std::unique_ptr<BlockSource> gridBlocksOn(const openvdb::GridBase& grid, const Lattice& lattice, double invisibleUpTo,
                                          bool backgroundVisible, std::size_t gaussiansEvaluated = 0) {
    if (const auto* grey = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
        return std::make_unique<GridBlocks<openvdb::FloatGrid>>(*grey, lattice, invisibleUpTo, backgroundVisible,
                                                                gaussiansEvaluated);
    }
    return std::make_unique<GridBlocks<openvdb::Vec3SGrid>>(dynamic_cast<const openvdb::Vec3SGrid&>(grid), lattice,
                                                            invisibleUpTo, backgroundVisible, gaussiansEvaluated);
}

/// Raises every log-scale to log(minScale), scaling the colour by the volume ratio
/// so that amplitude times the product of the scales, the integral, is unchanged.
GaussianParameters withMinimumFootprint(GaussianParameters params, float minScaleVoxels) {
    if (!(minScaleVoxels > 0.0f)) return params;
    const float floor = std::log(minScaleVoxels);
    for (std::size_t g = 0; g < params.count(); ++g) {
        float* logScale = params.at(kLogScales, g);
        float shrink = 0.0f;
        for (int a = 0; a < 3; ++a) {
            if (logScale[a] < floor) {
                shrink += logScale[a] - floor;
                logScale[a] = floor;
            }
        }
        float* colour = params.at(kColours, g);
        for (int c = 0; c < params.channels; ++c) colour[c] *= std::exp(shrink);
    }
    return params;
}

}  // namespace

const VolumeStatistics& RenderVolume::statistics() const {
    std::call_once(mStatisticsGathered, [this] { mStatistics = gatherStatistics(); });
    return mStatistics;
}

std::unique_ptr<BlockSource> RenderVolume::blocksOn(const Lattice& lattice, double invisibleUpTo) const {
    return gridBlocksOn(voxels(), lattice, invisibleUpTo, /*backgroundVisible=*/backgroundKey() > invisibleUpTo);
}

double RenderVolume::backgroundKey() const { return keyOf(background().data(), channels()); }

double RenderVolume::voxelMm() const {
    const openvdb::Vec3d spacing = axisSpacing(mWorldFromIndex);
    return std::min({spacing[0], spacing[1], spacing[2]});
}

double RenderVolume::finestStepVoxels(const openvdb::Vec3d& direction) const {
    const openvdb::Vec3d indexPerMm = mWorldFromIndex.inverse().transform3x3(direction.unit());
    const double facesPerMm = std::abs(indexPerMm[0]) + std::abs(indexPerMm[1]) + std::abs(indexPerMm[2]);
    return 1.0 / (kMostSamplesPerVoxelCrossed * facesPerMm * voxelMm());
}

GaussianRenderVolume::GaussianRenderVolume(const GaussianParameters& params, float cutoffSigmas,
                                           const Mat4d& worldFromIndex, const openvdb::Vec3i& dims,
                                           const ValueMapping& mapping, double valueMax, double foregroundAbove,
                                           float minScaleVoxels)
    : mField(withMinimumFootprint(params, minScaleVoxels), cutoffSigmas),
      mMapping(mapping),
      mForegroundAbove(foregroundAbove) {
    mWorldFromIndex = worldFromIndex;
    mBox = CoordBBox(Coord(0), Coord(dims) - Coord(1));
    mValueMax = valueMax;
}

GaussianRenderVolume::GaussianRenderVolume(const GaussianAsset& asset, float minScaleVoxels)
    : GaussianRenderVolume(asset.params, asset.cutoffSigmas, asset.worldFromIndex, asset.source.dims, asset.mapping,
                           asset.source.valueMax, asset.source.threshold.value_or(asset.source.valueMin),
                           minScaleVoxels) {}

std::array<float, 3> GaussianRenderVolume::background() const {
    std::array<float, 3> value{};
    for (int c = 0; c < channels(); ++c) value[c] = mMapping.toPhysicalFloat(0.0, c);
    return value;
}

std::size_t GaussianRenderVolume::evaluateVoxelsOnce() const {
    std::size_t evaluated = 0;
    std::call_once(mVoxelsEvaluated, [&] {
        FieldToGridSettings settings;
        settings.mapping = mMapping;
        settings.fieldBox = mBox;
        settings.evaluation = BlockEvaluation::Rows;  // a frame needs 16-bit opacity, not bit-for-bit sums
        mVoxels = fieldToGrid(mField, mWorldFromIndex, Lattice{mWorldFromIndex, mBox}, settings);
        evaluated = mField.gaussians().size();
    });
    return evaluated;
}

const openvdb::GridBase& GaussianRenderVolume::voxels() const {
    evaluateVoxelsOnce();
    return *mVoxels;
}

std::unique_ptr<BlockSource> GaussianRenderVolume::blocksOn(const Lattice& lattice, double invisibleUpTo) const {
    const std::size_t evaluated = evaluateVoxelsOnce();
    return gridBlocksOn(*mVoxels, lattice, invisibleUpTo, /*backgroundVisible=*/backgroundKey() > invisibleUpTo,
                        evaluated);
}

std::unique_ptr<BlockSource> GaussianRenderVolume::previewBlocksOn(const Lattice& lattice, double invisibleUpTo) const {
    // Luminance and value alike lie within scale * (sum of peaks) of the background's.
    const double headroom = (invisibleUpTo - backgroundKey()) / mMapping.scale;
    const float skipUpTo = std::isfinite(headroom) && headroom > 0.0 ? float(headroom) : -1.0f;
    return std::make_unique<GaussianBlocks>(mField, mWorldFromIndex, lattice, mBox, mMapping, skipUpTo,
                                            /*everyBlock=*/headroom < 0.0);
}

VolumeStatistics GaussianRenderVolume::gatherStatistics() const {
    VolumeStatistics stats;
    const int channels = mField.channels();
    const auto keyAt = [&](const Coord& ijk, std::vector<std::uint32_t>& hits) {
        const float x[3] = {float(ijk.x()), float(ijk.y()), float(ijk.z())};
        float value[3];
        mField.evaluate(x, value, hits);
        for (int c = 0; c < channels; ++c) value[c] = mMapping.toPhysicalFloat(value[c], c);
        return double(keyOf(value, channels));
    };
    std::vector<std::uint32_t> hits;
    stats.background = borderMedian(mBox, [&](const Coord& ijk) { return keyAt(ijk, hits); });
    // Voxel centres spread evenly over the box, kept where the field is content. Each
    // is a search of the field: on all cores, then kept in order.
    const std::uint64_t voxels = mBox.volume();
    const std::uint64_t stride = std::max<std::uint64_t>(1, voxels / (4 * kStatisticsSamples));
    const Coord dims = mBox.dim();
    std::vector<double> keys((voxels + stride - 1) / stride);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, keys.size()), [&](const tbb::blocked_range<std::size_t>& range) {
            std::vector<std::uint32_t> rangeHits;
            for (std::size_t s = range.begin(); s != range.end(); ++s) {
                const std::uint64_t n = s * stride;
                keys[s] = keyAt(Coord(int(n % dims.x()), int(n / dims.x() % dims.y()), int(n / dims.x() / dims.y())),
                                rangeHits);
            }
        });
    for (double key : keys) {
        if (key > mForegroundAbove) stats.values.push_back(float(key));
    }
    const bool anyBelow = std::any_of(stats.values.begin(), stats.values.end(), [](float v) { return v < -500.0f; });
    stats.hounsfield = anyBelow || stats.background < -500.0;
    return stats;
}

GridRenderVolume::GridRenderVolume(openvdb::GridBase::ConstPtr grid) : mGrid(std::move(grid)) {
    mFloat = openvdb::GridBase::constGrid<openvdb::FloatGrid>(mGrid);
    mColour = openvdb::GridBase::constGrid<openvdb::Vec3SGrid>(mGrid);
    if (!isVolumeGrid(*mGrid)) throw InputError("render", notAVolumeGrid(*mGrid));
    mWorldFromIndex = mGrid->transform().baseMap()->getAffineMap()->getMat4();
    mBox = volumeBox(*mGrid);
    if (mColour) {  // colours scale by the brightest channel, not the luminance
        double brightest = 0.0;
        for (auto v = mColour->cbeginValueOn(); v; ++v)
            brightest = std::max<double>({brightest, (*v)[0], (*v)[1], (*v)[2]});
        if (brightest > 0.0) mValueMax = brightest;
    }
}

std::array<float, 3> GridRenderVolume::background() const {
    if (mFloat) return {mFloat->background(), 0.0f, 0.0f};
    const openvdb::Vec3s colour = mColour->background();
    return {colour[0], colour[1], colour[2]};
}

namespace {

/// The key of every @a stride-th active value of @a grid, counted in the order of its
/// value iterator. Where every active value lies in a leaf, the leaves are read on
/// all cores, each from its first value's place in that order: the same keys, in the
/// same order, as one walk (on one core, a large CT's walk was slow).
template <typename GridT>
std::vector<float> everyStridethKey(const GridT& grid, std::size_t stride) {
    std::vector<float> keys;
    if (grid.tree().activeTileCount() > 0) {
        std::size_t n = 0;
        for (auto v = grid.cbeginValueOn(); v; ++v, ++n) {
            if (n % stride == 0) keys.push_back(float(keyOf(*v)));
        }
        return keys;
    }
    const openvdb::tree::LeafManager<const typename GridT::TreeType> leaves(grid.tree());
    std::vector<std::size_t> firstOf(leaves.leafCount() + 1, 0);  // each leaf's first value's place
    for (std::size_t l = 0; l < leaves.leafCount(); ++l) firstOf[l + 1] = firstOf[l] + leaves.leaf(l).onVoxelCount();
    keys.resize((firstOf.back() + stride - 1) / stride);
    tbb::parallel_for(std::size_t(0), leaves.leafCount(), [&](std::size_t l) {
        std::size_t n = firstOf[l];
        for (auto v = leaves.leaf(l).cbeginValueOn(); v; ++v, ++n) {
            if (n % stride == 0) keys[n / stride] = float(keyOf(*v));
        }
    });
    return keys;
}

}  // namespace

VolumeStatistics GridRenderVolume::gatherStatistics() const {
    VolumeStatistics stats;
    const auto gather = [&](const auto& grid) {
        const std::size_t stride = std::max<std::uint64_t>(1, grid.activeVoxelCount() / kStatisticsSamples);
        stats.values = everyStridethKey(grid, stride);
        const auto accessor = grid.getConstAccessor();
        stats.background = borderMedian(mBox, [&](const Coord& ijk) { return keyOf(accessor.getValue(ijk)); });
    };
    if (mFloat) {
        gather(*mFloat);
    } else {
        gather(*mColour);
    }
    const bool anyBelow = std::any_of(stats.values.begin(), stats.values.end(), [](float v) { return v < -500.0f; });
    stats.hounsfield = anyBelow || stats.background < -500.0;
    return stats;
}

}  // namespace gvr
