#include "GridBuilder.h"

#include "Error.h"
#include "LatticeSampler.h"
#include "LeafAssembly.h"
#include "Luminance.h"
#include "VolumeMetadata.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

namespace gvr {

namespace {

using openvdb::Coord;

/// Physical values of a dense volume stored as T, with NaN/Inf replaced when asked.
template <typename T>
class PhysicalValues {
public:
    PhysicalValues(const DenseVolume& volume, std::optional<float> nanTo)
        : mData(volume.data<T>()), mChannels(volume.channels), mSlope(volume.slope),
          mIntercept(volume.intercept), mNanTo(nanTo) {}

    float raw(std::size_t voxel, int channel) const {
        return float(mSlope * double(mData[voxel * mChannels + channel]) + mIntercept);
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

private:
    const T* mData;
    int mChannels;
    double mSlope, mIntercept;
    std::optional<float> mNanTo;
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

struct ChannelSum {
    openvdb::Vec3d sum{0.0};
    std::uint64_t count = 0;
};

/// Mean of the voxels at or below @a cut, per channel.
template <typename Values>
ChannelSum sumInactive(const Values& values, std::size_t voxelCount, double cut) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, voxelCount), ChannelSum{},
        [&](const tbb::blocked_range<std::size_t>& voxels, ChannelSum total) {
            for (std::size_t v = voxels.begin(); v != voxels.end(); ++v) {
                if (values.key(v) > cut) continue;
                for (int c = 0; c < values.channels(); ++c) total.sum[c] += values.value(v, c);
                ++total.count;
            }
            return total;
        },
        [](ChannelSum a, const ChannelSum& b) {
            a.sum += b.sum;
            a.count += b.count;
            return a;
        });
}

template <typename ValueT, typename Values>
ValueT voxelValue(const Values& values, std::size_t voxel) {
    if constexpr (std::is_same_v<ValueT, openvdb::Vec3s>) {
        return ValueT(values.value(voxel, 0), values.value(voxel, 1), values.value(voxel, 2));
    } else {
        return values.value(voxel, 0);
    }
}

/// Fills the leaf at @a origin; returns null when none of its voxels is active.
template <typename LeafT, typename Values>
std::unique_ptr<LeafT> buildLeaf(const Values& values, const DenseVolume& volume,
                                 const Coord& origin, double cut,
                                 const typename LeafT::ValueType& background) {
    auto leaf = std::make_unique<LeafT>(origin, background, false);
    const Coord end = Coord::minComponent(origin + Coord(LeafT::DIM),
                                          Coord(int(volume.dims[0]), int(volume.dims[1]),
                                                int(volume.dims[2])));
    for (int k = origin.z(); k < end.z(); ++k) {
        for (int j = origin.y(); j < end.y(); ++j) {
            std::size_t voxel = (std::size_t(k) * volume.dims[1] + j) * volume.dims[0] + origin.x();
            for (int i = origin.x(); i < end.x(); ++i, ++voxel) {
                if (values.key(voxel) <= cut) continue;
                leaf->setValueOn(LeafT::coordToOffset(Coord(i, j, k)),
                                 voxelValue<typename LeafT::ValueType>(values, voxel));
            }
        }
    }
    return leaf->isEmpty() ? nullptr : std::move(leaf);
}

/// Every leaf of the volume's box, made in parallel.
template <typename GridT, typename Values>
typename GridT::Ptr buildSparseGrid(const Values& values, const DenseVolume& volume, double cut,
                                    const typename GridT::ValueType& background,
                                    const ProgressFn& progress) {
    using LeafT = typename GridT::TreeType::LeafNodeType;
    const std::vector<Coord> origins = blockOrigins(
        openvdb::CoordBBox(Coord(0), Coord(int(volume.dims[0]), int(volume.dims[1]), int(volume.dims[2])) - Coord(1)));
    return assembleGrid<GridT>(
        origins, background,
        [&](const Coord& origin) { return buildLeaf<LeafT>(values, volume, origin, cut, background); },
        progress);
}

openvdb::math::Transform::Ptr transformOf(const DenseVolume& volume, const std::string& file) {
    const openvdb::Mat3d linear = volume.worldFromIndex.getMat3();
    std::ostringstream determinant;
    determinant << "(its determinant is " << linear.det() << ")";
    const openvdb::Vec3d spacing = axisSpacing(volume.worldFromIndex);
    const double scale = spacing[0] * spacing[1] * spacing[2];
    if (!(std::abs(linear.det()) > 1e-9 * scale) || !std::isfinite(linear.det())) {
        throw InputError(file, "degenerate orientation matrix " + determinant.str());
    }
    try {
        return openvdb::math::Transform::createLinearTransform(volume.worldFromIndex);
    } catch (const openvdb::ArithmeticError&) {  // OpenVDB's own, absolute, test of the determinant
        throw InputError(file, "voxels too small for OpenVDB: orientation matrix " + determinant.str());
    }
}

template <typename T>
openvdb::GridBase::Ptr buildTyped(const DenseVolume& volume, const GridBuildSettings& settings,
                                  const ProgressFn& progress) {
    const PhysicalValues<T> values(volume, settings.nanTo);
    const std::size_t voxelCount = volume.voxelCount();
    const Range range = scanRange(values, voxelCount, settings.nanTo.has_value());
    if (range.nonFinite > 0) {
        throw InputError(settings.sourceFile,
                         std::to_string(range.nonFinite) +
                             " voxels are NaN or Inf; pass --nan-to VALUE to replace them");
    }
    const double cut = settings.threshold.value_or(range.min);
    const ChannelSum inactive = sumInactive(values, voxelCount, cut);
    const openvdb::Vec3d fallback(volume.channels == 1 ? range.min : 0.0);
    const openvdb::Vec3d background =
        inactive.count > 0 ? inactive.sum / double(inactive.count) : fallback;

    openvdb::GridBase::Ptr grid;
    if (volume.channels == 1) {
        grid = buildSparseGrid<openvdb::FloatGrid>(values, volume, cut, float(background[0]), progress);
        grid->setName("density");
        grid->setGridClass(openvdb::GRID_FOG_VOLUME);  // what Blender and Houdini expect of density
    } else {
        grid = buildSparseGrid<openvdb::Vec3SGrid>(values, volume, cut, openvdb::Vec3s(background),
                                                   progress);
        grid->setName("color");
    }
    grid->setTransform(transformOf(volume, settings.sourceFile));

    VolumeMetadata metadata;
    metadata.sourceFile = settings.sourceFile;
    metadata.modality = settings.modality.empty() ? volume.modality : settings.modality;
    metadata.sourceType = sampleTypeName(volume.type);
    metadata.channels = volume.channels;
    metadata.dims = openvdb::Vec3i(int(volume.dims[0]), int(volume.dims[1]), int(volume.dims[2]));
    metadata.spacingMm = axisSpacing(volume.worldFromIndex);
    metadata.valueMin = range.min;
    metadata.valueMax = range.max;
    metadata.background = volume.channels == 1 ? background[0] : luminance(background);
    metadata.threshold = settings.threshold;
    writeVolumeMetadata(metadata, *grid);
    return grid;
}

}  // namespace

openvdb::GridBase::Ptr buildGrid(const DenseVolume& volume, const GridBuildSettings& settings,
                                 const ProgressFn& progress) {
    if (volume.channels != 1 && volume.channels != 3) {
        throw InputError(settings.sourceFile, "has " + std::to_string(volume.channels) +
                                                  " channels; gvr handles grey (1) or RGB (3)");
    }
    return dispatchSampleType(volume.type, [&](auto sample) {
        return buildTyped<decltype(sample)>(volume, settings, progress);
    });
}

}  // namespace gvr
