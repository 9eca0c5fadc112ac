#include "io/GridBuilder.h"

#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/LatticeSampler.h"
#include "pipeline/LeafAssembly.h"
#include "pipeline/Luminance.h"
#include "pipeline/VolumeBorder.h"
#include "pipeline/VolumeMetadata.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

namespace gvr {

namespace {

using openvdb::Coord;

/// readSlab(first, count): slices [first, first + count) of the volume.
using ReadSlab = std::function<const DenseVolume&(std::int64_t first, std::int64_t count)>;

/// Physical values of a dense volume stored as T, with NaN/Inf replaced when asked.
template <typename T>
class PhysicalValues {
public:
    PhysicalValues(const DenseVolume& volume, std::optional<float> nanTo)
        : mData(volume.data<T>()),
          mChannels(volume.channels),
          mSlope(volume.slope),
          mIntercept(volume.intercept),
          mNanTo(nanTo) {
        if constexpr (kTabulated) {
            mTable.resize(std::size_t(1) << (8 * sizeof(T)));
            for (std::size_t stored = 0; stored < mTable.size(); ++stored) {
                mTable[stored] = convert(T(static_cast<Unsigned>(stored)));
            }
        }
    }

    float raw(std::size_t voxel, int channel) const {
        const T stored = mData[voxel * mChannels + channel];
        if constexpr (kTabulated) return mTable[static_cast<Unsigned>(stored)];
        return convert(stored);
    }

    float value(std::size_t voxel, int channel) const {
        const float v = raw(voxel, channel);
        return (mNanTo && !std::isfinite(v)) ? *mNanTo : v;
    }

    /// What thresholds compare: the value, or the Rec. 709 luminance for RGB.
    float key(std::size_t voxel) const {
        if (mChannels == 1) return value(voxel, 0);
        const float rgb[3] = {value(voxel, 0), value(voxel, 1), value(voxel, 2)};
        return float(luminance(rgb));
    }

    bool isFinite(std::size_t voxel) const {
        for (int c = 0; c < mChannels; ++c) {
            if (!std::isfinite(raw(voxel, c))) return false;
        }
        return true;
    }

    int channels() const { return mChannels; }

    /// Whether the grid's float32 can change a value: 32-bit integers that the
    /// mapping keeps integers (slope 1, an integral intercept), beyond 2^24.
    bool mayRound() const {
        return std::is_integral_v<T> && sizeof(T) == 4 && mSlope == 1.0 && mIntercept == std::floor(mIntercept);
    }

    /// True when float32 changes a sample of @a voxel (16777217 becomes 16777216).
    bool rounds(std::size_t voxel) const {
        for (int c = 0; c < mChannels; ++c) {
            const double exact = mSlope * double(mData[voxel * mChannels + c]) + mIntercept;
            if (double(float(exact)) != exact) return true;
        }
        return false;
    }

private:
    /// 8- and 16-bit samples take their physical value from a table of every
    /// stored value: ingest converts each sample several times.
    static constexpr bool kTabulated = std::is_integral_v<T> && sizeof(T) <= 2;
    using Unsigned = std::make_unsigned_t<std::conditional_t<std::is_integral_v<T>, T, int>>;

    float convert(T stored) const { return float(mSlope * double(stored) + mIntercept); }

    const T* mData;
    int mChannels;
    double mSlope, mIntercept;
    std::optional<float> mNanTo;
    std::vector<float> mTable;
};

struct Range {
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    std::uint64_t nonFinite = 0;

    Range merged(const Range& other) const {
        return {std::min(min, other.min), std::max(max, other.max), nonFinite + other.nonFinite};
    }
};

template <typename Values>
Range scanRange(const Values& values, std::size_t voxelCount, bool replacesNonFinite) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, voxelCount), Range{},
        [&](const tbb::blocked_range<std::size_t>& voxels, Range range) {
            for (std::size_t v = voxels.begin(); v != voxels.end(); ++v) {
                if (!replacesNonFinite && !values.isFinite(v)) {
                    ++range.nonFinite;
                    continue;
                }
                const double key = values.key(v);
                range.min = std::min(range.min, key);
                range.max = std::max(range.max, key);
            }
            return range;
        },
        [](const Range& a, const Range& b) { return a.merged(b); });
}

/// Voxels of a slab whose integers float32 rounds (PhysicalValues::rounds).
template <typename Values>
std::uint64_t countRounded(const Values& values, std::size_t voxelCount) {
    if (!values.mayRound()) return 0;
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, voxelCount), std::uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& voxels, std::uint64_t rounded) {
            for (std::size_t v = voxels.begin(); v != voxels.end(); ++v) rounded += values.rounds(v) ? 1 : 0;
            return rounded;
        },
        std::plus<>());
}

struct ChannelSum {
    openvdb::Vec3d sum{0.0};
    std::uint64_t count = 0;

    void add(const ChannelSum& other) {
        sum += other.sum;
        count += other.count;
    }
};

/// What a pass over a slab's leaves finds besides the leaves: the range of the
/// finite values and the sum of the voxels that the cut leaves inactive.
/// The inactive voxels: their sum, and apart the ones at their lowest value, which
/// on a CT is the scanner's padding outside the reconstruction circle (-3024 HU, say).
struct InactiveTally {
    ChannelSum all, atLowest;
    double lowest = std::numeric_limits<double>::infinity();

    void add(double key, const openvdb::Vec3d& value) {
        if (key < lowest) {
            lowest = key;
            atLowest = {};
        }
        const ChannelSum one{value, 1};
        if (key == lowest) atLowest.add(one);
        all.add(one);
    }
    void add(const InactiveTally& other) {
        all.add(other.all);
        if (other.lowest < lowest) {
            lowest = other.lowest;
            atLowest = other.atLowest;
        } else if (other.lowest == lowest) {
            atLowest.add(other.atLowest);
        }
    }
};

struct SlabTally {
    Range range;
    InactiveTally inactive;

    void add(const SlabTally& other) {
        range = range.merged(other.range);
        inactive.add(other.inactive);
    }
};

template <typename ValueT, typename Values>
ValueT voxelValue(const Values& values, std::size_t voxel) {
    if constexpr (std::is_same_v<ValueT, openvdb::Vec3s>) {
        return ValueT(values.value(voxel, 0), values.value(voxel, 1), values.value(voxel, 2));
    } else {
        return values.value(voxel, 0);
    }
}

/// Fills the leaf at @a origin from @a slab, which holds the slices from @a firstSlice
/// on, and tallies its voxels; null when none of them is active.
template <typename LeafT, typename Values>
std::unique_ptr<LeafT> buildLeaf(const Values& values, const DenseVolume& slab, std::int64_t firstSlice,
                                 const Coord& origin, double cut, double cutAbove,
                                 const typename LeafT::ValueType& background, bool replacesNonFinite,
                                 SlabTally& tally) {
    std::unique_ptr<LeafT> leaf;  // made at the first active voxel: most leaves of a large volume stay empty
    const Coord end = Coord::minComponent(origin + Coord(LeafT::DIM),
                                          Coord(int(slab.dims[0]), int(slab.dims[1]), int(firstSlice + slab.dims[2])));
    for (int k = origin.z(); k < end.z(); ++k) {
        for (int j = origin.y(); j < end.y(); ++j) {
            std::size_t voxel = (std::size_t(k - firstSlice) * slab.dims[1] + j) * slab.dims[0] + origin.x();
            for (int i = origin.x(); i < end.x(); ++i, ++voxel) {
                if (!replacesNonFinite && !values.isFinite(voxel)) {
                    ++tally.range.nonFinite;
                    continue;
                }
                const double key = values.key(voxel);
                tally.range.min = std::min(tally.range.min, key);
                tally.range.max = std::max(tally.range.max, key);
                if (key <= cut || key >= cutAbove) {
                    openvdb::Vec3d value(0.0);
                    for (int c = 0; c < values.channels(); ++c) value[c] = values.value(voxel, c);
                    tally.inactive.add(key, value);
                    continue;
                }
                if (!leaf) leaf = std::make_unique<LeafT>(origin, background, false);
                leaf->setValueOn(LeafT::coordToOffset(Coord(i, j, k)),
                                 voxelValue<typename LeafT::ValueType>(values, voxel));
            }
        }
    }
    return leaf;
}

/// The leaves of a slab's slices, and their tally, added up leaf by leaf in a fixed
/// order so that the sums do not depend on the threads. A slab starts on a leaf
/// boundary, so no leaf is shared with another slab.
template <typename GridT, typename Values>
SlabTally addSlabLeaves(GridT& grid, const Values& values, const DenseVolume& slab, std::int64_t firstSlice, double cut,
                        double cutAbove, bool replacesNonFinite, ProgressCounter& counter) {
    using LeafT = typename GridT::TreeType::LeafNodeType;
    const Coord first(0, 0, int(firstSlice));
    const std::vector<Coord> origins = blockOrigins(openvdb::CoordBBox(
        first, Coord(int(slab.dims[0]) - 1, int(slab.dims[1]) - 1, int(firstSlice + slab.dims[2]) - 1)));
    const Coord blocks((int(slab.dims[0]) + kBlockDim - 1) / kBlockDim, (int(slab.dims[1]) + kBlockDim - 1) / kBlockDim,
                       (int(slab.dims[2]) + kBlockDim - 1) / kBlockDim);
    const auto indexOf = [&](const Coord& origin) {  // blockOrigins() runs z, y, x
        const Coord offset = origin - first;
        return (std::size_t(offset.z() / kBlockDim) * blocks.y() + offset.y() / kBlockDim) * blocks.x() +
               offset.x() / kBlockDim;
    };
    std::vector<SlabTally> tallies(origins.size());
    const typename GridT::ValueType placeholder = grid.background();
    addLeaves(
        grid, origins,
        [&](const Coord& origin) {
            return buildLeaf<LeafT>(values, slab, firstSlice, origin, cut, cutAbove, placeholder, replacesNonFinite,
                                    tallies[indexOf(origin)]);
        },
        counter);
    SlabTally total;
    for (const SlabTally& tally : tallies) total.add(tally);
    return total;
}

/// volume.worldFromIndex after mirroring the index axes that @a flip names:
/// index i of a flipped axis stands where n - 1 - i stood.
openvdb::math::Mat4d flippedWorldFromIndex(const DenseVolume& volume, const std::array<bool, 3>& flip) {
    openvdb::math::Mat4d mirror = openvdb::math::Mat4d::identity();
    for (int axis = 0; axis < 3; ++axis) {
        if (!flip[axis]) continue;
        mirror(axis, axis) = -1.0;
        mirror(3, axis) = double(volume.dims[axis] - 1);
    }
    return mirror * volume.worldFromIndex;  // row vectors: mirror first, then place
}

openvdb::math::Transform::Ptr transformOf(const DenseVolume& volume, const GridBuildSettings& settings) {
    const std::string& file = settings.sourceFile;
    const openvdb::math::Mat4d worldFromIndex = flippedWorldFromIndex(volume, settings.flip);
    const openvdb::Mat3d linear = worldFromIndex.getMat3();
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            if (!std::isfinite(worldFromIndex(i, j))) {
                throw InputError(file, "the voxel spacing or orientation is not a finite number (NaN or Inf)");
            }
        }
    }
    std::ostringstream determinant;
    determinant << "(its determinant is " << linear.det() << ")";
    const openvdb::Vec3d spacing = axisSpacing(volume.worldFromIndex);
    const double scale = spacing[0] * spacing[1] * spacing[2];
    if (!(std::abs(linear.det()) > 1e-9 * scale) || !std::isfinite(linear.det())) {
        throw InputError(file, "degenerate orientation matrix " + determinant.str());
    }
    try {
        return openvdb::math::Transform::createLinearTransform(worldFromIndex);
    } catch (const openvdb::ArithmeticError&) {  // OpenVDB's own, absolute, test of the determinant
        throw InputError(file, "voxels too small for OpenVDB: orientation matrix " + determinant.str());
    }
}

/// What became of one slab: the cut its leaves were built with and the sum of the
/// voxels that cut left inactive.
struct SlabRecord {
    std::int64_t first = 0, count = 0;
    double cut = 0;
    InactiveTally inactive;
};

/// Builds the grid one slab at a time, so that only one slab of dense samples is
/// held. Without a threshold the cut is the volume's minimum, which is known only
/// at the end: each slab is cut at the minimum seen so far, and the few slabs read
/// before the minimum fell (usually none: padding and air come early) are read
/// and built again at the final cut; so are those with inactive voxels when the
/// minimum turns out to be no background (minimumIsNoBackground).
template <typename T, typename GridT>
class SlabBuild {
public:
    SlabBuild(const DenseVolume& layout, const GridBuildSettings& settings, const ProgressFn& progress)
        : mLayout(layout),
          mSettings(settings),
          mGrid(GridT::create()),  // its background is set once the inactive voxels are known
          mCounter(progress, leafCount(layout)) {}

    /// @param readSlab  readSlab(first, count) returns those slices as a DenseVolume
    typename GridT::Ptr run(std::int64_t slabSlices, const ReadSlab& readSlab) {
        const std::int64_t slices = mLayout.dims[2];
        for (std::int64_t first = 0; first < slices; first += slabSlices) {
            const std::int64_t count = std::min(slabSlices, slices - first);
            mRecords.push_back(addSlab(readSlab(first, count), first, count));
        }
        if (mRange.nonFinite > 0) {
            throw InputError(mSettings.sourceFile, std::to_string(mRange.nonFinite) +
                                                       " voxels are NaN or Inf; pass `nan_to=VALUE` to replace them");
        }
        for (SlabRecord& record : mRecords) {
            if (record.cut != finalCut()) record = rebuildSlab(readSlab(record.first, record.count), record);
        }
        if (minimumIsNoBackground()) {
            mMinimumKept = true;
            for (SlabRecord& record : mRecords) {
                if (record.inactive.all.count > 0) record = rebuildSlab(readSlab(record.first, record.count), record);
            }
        }
        mBackground = surroundings();
        mGrid->tree().root().setBackground(backgroundValue(), /*updateChildNodes=*/true);
        return mGrid;
    }

    const Range& range() const { return mRange; }
    std::uint64_t roundedVoxels() const { return mRounded; }
    /// With only a cut from above, the darkest voxels are the subject, not its
    /// background; so they are when they are few (minimumIsNoBackground).
    double finalCut() const {
        if (mSettings.keepEveryVoxel) return -std::numeric_limits<double>::infinity();
        if (mSettings.threshold) return *mSettings.threshold;
        return mSettings.thresholdAbove || mMinimumKept ? -std::numeric_limits<double>::infinity() : mRange.min;
    }
    double cutAbove() const {
        if (mSettings.keepEveryVoxel) return std::numeric_limits<double>::infinity();
        return mSettings.thresholdAbove.value_or(std::numeric_limits<double>::infinity());
    }

    /// What inactive voxels stand for, and what samplers meet beyond the volume's
    /// faces (known once run() has built the grid).
    const openvdb::Vec3d& background() const { return mBackground; }

    /// The value and count of the padding that background() left out, if it did.
    std::optional<std::pair<double, std::uint64_t>> padding() const {
        const InactiveTally inactive = inactiveTally();
        if (!paddingSetApart(inactive)) return std::nullopt;
        return std::make_pair(inactive.lowest, inactive.atLowest.count);
    }

private:
    static constexpr double kPaddingShare = 0.05;
    /// A colour volume whose darkest voxels are fewer than this share of it has no
    /// dark background to cut: a section photographed on paper, whose darkest voxel
    /// is the specimen's.
    static constexpr double kBackgroundShare = 0.01;

    bool minimumIsNoBackground() const {
        const double voxels = double(mLayout.dims[0]) * double(mLayout.dims[1]) * double(mLayout.dims[2]);
        return mLayout.channels == 3 && !mSettings.threshold && !mSettings.thresholdAbove &&
               double(inactiveTally().all.count) < kBackgroundShare * voxels;
    }

    /// The mean of the inactive voxels above the lowest value when the lowest holds
    /// at least kPaddingShare of them (a CT's padding, which would drag air's -1000
    /// HU to an unphysical -1800), else the mean of all of them. With none, the
    /// minimum of grey data, and the median of a colour volume's faces, channel by
    /// channel (VolumeBorder.h: the paper or the medium of a section): black beside
    /// the white paper of the faces blended into a grey shell there, which the `rgb`
    /// preset, dense away from the faces' colour, showed as a box.
    openvdb::Vec3d surroundings() const {
        const InactiveTally inactive = inactiveTally();
        if (inactive.all.count == 0) return mLayout.channels == 1 ? openvdb::Vec3d(mRange.min) : facesMedian();
        if (paddingSetApart(inactive)) {
            return (inactive.all.sum - inactive.atLowest.sum) / double(inactive.all.count - inactive.atLowest.count);
        }
        return inactive.all.sum / double(inactive.all.count);
    }

    /// The median of the grid's values on the volume's faces, channel by channel.
    openvdb::Vec3d facesMedian() const {
        const openvdb::CoordBBox box(
            Coord(0), Coord(int(mLayout.dims[0]) - 1, int(mLayout.dims[1]) - 1, int(mLayout.dims[2]) - 1));
        const auto accessor = mGrid->getConstAccessor();
        openvdb::Vec3d median(0.0);
        for (int c = 0; c < mLayout.channels; ++c) {
            median[c] = borderMedian(box, [&](const Coord& ijk) {
                const typename GridT::ValueType value = accessor.getValue(ijk);
                if constexpr (std::is_same_v<typename GridT::ValueType, openvdb::Vec3s>) {
                    return double(value[c]);
                } else {
                    return double(value);
                }
            });
        }
        return median;
    }

    InactiveTally inactiveTally() const {
        InactiveTally inactive;
        for (const SlabRecord& record : mRecords) inactive.add(record.inactive);
        return inactive;
    }

    bool paddingSetApart(const InactiveTally& inactive) const {
        return mLayout.channels == 1 && inactive.atLowest.count < inactive.all.count &&
               double(inactive.atLowest.count) >= kPaddingShare * double(inactive.all.count);
    }

    static std::size_t leafCount(const DenseVolume& layout) {
        std::size_t leaves = 1;
        for (std::int64_t d : layout.dims) leaves *= std::size_t((d + kBlockDim - 1) / kBlockDim);
        return leaves;
    }

    /// Without a threshold the cut must come from this slab's minimum too, so its
    /// range is scanned first; with one, the leaves' pass finds the range.
    SlabRecord addSlab(const DenseVolume& slab, std::int64_t first, std::int64_t count) {
        const PhysicalValues<T> values(slab, mSettings.nanTo);
        const bool replacesNonFinite = mSettings.nanTo.has_value();
        if (!mSettings.threshold) mRange = mRange.merged(scanRange(values, slab.voxelCount(), replacesNonFinite));
        mRounded += countRounded(values, slab.voxelCount());
        SlabRecord record{first, count, finalCut(), {}};
        const SlabTally tally =
            addSlabLeaves(*mGrid, values, slab, first, record.cut, cutAbove(), replacesNonFinite, mCounter);
        if (mSettings.threshold) mRange = mRange.merged(tally.range);
        record.inactive = tally.inactive;
        return record;
    }

    SlabRecord rebuildSlab(const DenseVolume& slab, SlabRecord record) {
        const PhysicalValues<T> values(slab, mSettings.nanTo);
        record.cut = finalCut();
        const ProgressFn none;  // the first pass already counted these leaves
        ProgressCounter silent(none, 0);
        record.inactive = addSlabLeaves(*mGrid, values, slab, record.first, record.cut, cutAbove(),
                                        mSettings.nanTo.has_value(), silent)
                              .inactive;
        return record;
    }

    typename GridT::ValueType backgroundValue() const {
        const openvdb::Vec3d value = background();
        if constexpr (std::is_same_v<typename GridT::ValueType, openvdb::Vec3s>) {
            return openvdb::Vec3s(value);
        } else {
            return float(value[0]);
        }
    }

    const DenseVolume& mLayout;
    const GridBuildSettings& mSettings;
    typename GridT::Ptr mGrid;
    bool mMinimumKept = false;  ///< minimumIsNoBackground: nothing is cut from below
    openvdb::Vec3d mBackground{0.0};
    ProgressCounter mCounter;
    Range mRange;
    std::uint64_t mRounded = 0;
    std::vector<SlabRecord> mRecords;
};

void describeGrid(const DenseVolume& layout, const GridBuildSettings& settings, const Range& range,
                  const openvdb::Vec3d& background, const std::optional<std::pair<double, std::uint64_t>>& padding,
                  std::uint64_t roundedVoxels, openvdb::GridBase& grid) {
    if (layout.channels == 1) {
        grid.setName("density");
        grid.setGridClass(openvdb::GRID_FOG_VOLUME);  // what Blender and Houdini expect of density
    } else {
        grid.setName("color");
    }
    grid.setTransform(transformOf(layout, settings));

    VolumeMetadata metadata;
    metadata.sourceFile = settings.sourceFile;
    metadata.modality = settings.modality.empty() ? layout.modality : settings.modality;
    metadata.sourceType = sampleTypeName(layout.type);
    metadata.channels = layout.channels;
    metadata.dims = openvdb::Vec3i(int(layout.dims[0]), int(layout.dims[1]), int(layout.dims[2]));
    metadata.spacingMm = axisSpacing(layout.worldFromIndex);
    metadata.valueMin = range.min;
    metadata.valueMax = range.max;
    metadata.background = layout.channels == 1 ? background[0] : luminance(background);
    metadata.threshold = settings.threshold;
    metadata.thresholdAbove = settings.thresholdAbove;
    if (padding) {
        metadata.padding = padding->first;
        metadata.paddingVoxels = padding->second;
    }
    metadata.roundedVoxels = roundedVoxels;
    metadata.markedPadding = layout.markedPadding;
    metadata.storedSlope = layout.slope;
    metadata.storedIntercept = layout.intercept;
    metadata.niftiCodes = layout.niftiCodes;
    writeVolumeMetadata(metadata, grid);
}

/// A CT whose header says so, given no threshold, loses its air (-1000 HU) and
/// keeps its lungs (about -890 HU); other data keep everything above their minimum.
GridBuildSettings withDefaultThreshold(const DenseVolume& layout, GridBuildSettings settings) {
    const std::string modality = settings.modality.empty() ? layout.modality : settings.modality;
    if (!settings.threshold && !settings.keepEveryVoxel && layout.channels == 1 && modality == "CT") {
        settings.threshold = kCtDefaultThreshold;
    }
    return settings;
}

template <typename T, typename GridT>
openvdb::GridBase::Ptr buildTyped(const DenseVolume& layout, std::int64_t slabSlices, const ReadSlab& readSlab,
                                  const GridBuildSettings& settings, const ProgressFn& progress) {
    transformOf(layout, settings);  // a bad matrix fails before any slab is read
    const GridBuildSettings chosen = withDefaultThreshold(layout, settings);
    SlabBuild<T, GridT> build(layout, chosen, progress);
    typename GridT::Ptr grid = build.run(slabSlices, readSlab);
    describeGrid(layout, chosen, build.range(), build.background(), build.padding(), build.roundedVoxels(), *grid);
    return grid;
}

openvdb::GridBase::Ptr buildFromSlabs(const DenseVolume& layout, std::int64_t slabSlices, const ReadSlab& readSlab,
                                      const GridBuildSettings& settings, const ProgressFn& progress) {
    settings.validate();
    if (layout.channels != 1 && layout.channels != 3) {
        throw InputError(settings.sourceFile,
                         "has " + std::to_string(layout.channels) + " channels; gvr handles grey (1) or RGB (3)");
    }
    return dispatchSampleType(layout.type, [&](auto sample) {
        using T = decltype(sample);
        if (layout.channels == 1)
            return buildTyped<T, openvdb::FloatGrid>(layout, slabSlices, readSlab, settings, progress);
        return buildTyped<T, openvdb::Vec3SGrid>(layout, slabSlices, readSlab, settings, progress);
    });
}

/// Slabs of whole leaves, about @a slabBytes of samples each.
std::int64_t slabSlicesFor(const SliceSource& source, std::uint64_t slabBytes) {
    const std::uint64_t leafBytes = source.sliceBytes() * kBlockDim;
    return std::max<std::int64_t>(1, std::int64_t(slabBytes / leafBytes)) * kBlockDim;
}

}  // namespace

void GridBuildSettings::validate() const {
    if (threshold && !std::isfinite(*threshold)) throw InputError("`threshold`", "must be a finite number");
    if (thresholdAbove) {
        if (!std::isfinite(*thresholdAbove)) throw InputError("`threshold_above`", "must be a finite number");
        if (threshold && *thresholdAbove <= *threshold) {
            throw InputError("`threshold_above`", "must lie above `threshold`, or nothing stays active");
        }
    }
    // A double such as 1e39 arrives here as an infinite float.
    if (nanTo && !std::isfinite(*nanTo)) {
        throw InputError("`nan_to`", "must be a finite number, of float32's range (at most 3.4e38 in magnitude)");
    }
}

openvdb::GridBase::Ptr buildGrid(const DenseVolume& volume, const GridBuildSettings& settings,
                                 const ProgressFn& progress) {
    const auto wholeVolume = [&](std::int64_t, std::int64_t) -> const DenseVolume& { return volume; };
    return buildFromSlabs(volume, volume.dims[2], wholeVolume, settings, progress);
}

openvdb::GridBase::Ptr buildGrid(const SliceSource& source, const GridBuildSettings& settings,
                                 const ProgressFn& progress) {
    const DenseVolume& layout = source.layout();  // its dimensions were checked when the source was opened
    DenseVolume slab;
    const auto nextSlab = [&](std::int64_t first, std::int64_t count) -> const DenseVolume& {
        checkSlabFitsInMemory(source.culprit(), {layout.dims[0], layout.dims[1], count}, layout.channels,
                              bytesPerSample(layout.type),
                              " (slices " + std::to_string(first) + " on, of " + std::to_string(layout.dims[2]) +
                                  "; a higher `threshold` keeps fewer voxels)");
        source.readSlab(first, count, slab);
        return slab;
    };
    return buildFromSlabs(layout, slabSlicesFor(source, settings.slabBytes), nextSlab, settings, progress);
}

}  // namespace gvr
