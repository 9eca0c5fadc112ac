#include "pipeline/VolumeMetadata.h"

#include "pipeline/Error.h"
#include "pipeline/SampleType.h"

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {

template <typename MetaT, typename T>
std::optional<T> findMeta(const openvdb::GridBase& grid, const std::string& key) {
    if (auto meta = grid.getMetadata<MetaT>(key)) return meta->value();
    return std::nullopt;
}

}  // namespace

std::uint64_t VolumeMetadata::rawSourceBytes() const {
    const std::uint64_t voxels = std::uint64_t(dims.x()) * dims.y() * dims.z();
    return voxels * channels * bytesPerSample(sampleTypeFromName(sourceType, sourceFile));
}

bool samePlacement(const openvdb::math::Mat4d& a, const openvdb::math::Mat4d& b, double relativeTolerance) {
    // eq() asks !(|a - b| > tolerance), which holds for NaN: a matrix with NaN places nothing.
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            if (!std::isfinite(a(r, c)) || !std::isfinite(b(r, c))) return false;
        }
    }
    double scale = 0.0;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 3; ++c) scale = std::max(scale, std::abs(a(r, c)));
    }
    return a.eq(b, relativeTolerance * std::max(1.0, scale));
}

openvdb::Vec3d axisSpacing(const openvdb::math::Mat4d& worldFromIndex) {
    openvdb::Vec3d spacing;
    for (int axis = 0; axis < 3; ++axis) spacing[axis] = worldFromIndex.row(axis).getVec3().length();
    return spacing;
}

void writeVolumeMetadata(const VolumeMetadata& m, openvdb::GridBase& grid) {
    grid.insertMeta("gvr_source_file", openvdb::StringMetadata(m.sourceFile));
    grid.insertMeta("gvr_modality", openvdb::StringMetadata(m.modality));
    grid.insertMeta("gvr_source_type", openvdb::StringMetadata(m.sourceType));
    grid.insertMeta("gvr_channels", openvdb::Int32Metadata(m.channels));
    grid.insertMeta("gvr_dims", openvdb::Vec3IMetadata(m.dims));
    grid.insertMeta("gvr_spacing_mm", openvdb::Vec3DMetadata(m.spacingMm));
    grid.insertMeta("gvr_value_min", openvdb::DoubleMetadata(m.valueMin));
    grid.insertMeta("gvr_value_max", openvdb::DoubleMetadata(m.valueMax));
    grid.insertMeta("gvr_background", openvdb::DoubleMetadata(m.background));
    if (m.threshold) grid.insertMeta("gvr_threshold", openvdb::DoubleMetadata(*m.threshold));
    if (m.thresholdAbove) grid.insertMeta("gvr_threshold_above", openvdb::DoubleMetadata(*m.thresholdAbove));
    if (m.padding) {
        grid.insertMeta("gvr_padding_value", openvdb::DoubleMetadata(*m.padding));
        grid.insertMeta("gvr_padding_voxels", openvdb::Int64Metadata(std::int64_t(m.paddingVoxels)));
    }
    if (m.markedPadding) grid.insertMeta("gvr_marked_padding", openvdb::DoubleMetadata(*m.markedPadding));
    if (m.roundedVoxels > 0)
        grid.insertMeta("gvr_rounded_voxels", openvdb::Int64Metadata(std::int64_t(m.roundedVoxels)));
    grid.insertMeta("gvr_stored_slope", openvdb::DoubleMetadata(m.storedSlope));
    grid.insertMeta("gvr_stored_intercept", openvdb::DoubleMetadata(m.storedIntercept));
    if (m.niftiCodes) {
        const NiftiCodes& codes = *m.niftiCodes;
        grid.insertMeta("gvr_nifti_codes", openvdb::Vec3IMetadata({codes.sform, codes.qform, codes.xyztUnits}));
    }
}

std::optional<VolumeMetadata> readVolumeMetadata(const openvdb::GridBase& grid) {
    auto sourceType = findMeta<openvdb::StringMetadata, std::string>(grid, "gvr_source_type");
    auto dims = findMeta<openvdb::Vec3IMetadata, openvdb::Vec3i>(grid, "gvr_dims");
    if (!sourceType || !dims) return std::nullopt;

    VolumeMetadata m;
    m.sourceType = *sourceType;
    m.dims = *dims;
    m.sourceFile = findMeta<openvdb::StringMetadata, std::string>(grid, "gvr_source_file").value_or("");
    m.modality = findMeta<openvdb::StringMetadata, std::string>(grid, "gvr_modality").value_or("unknown");
    m.channels = findMeta<openvdb::Int32Metadata, int>(grid, "gvr_channels").value_or(1);
    m.spacingMm =
        findMeta<openvdb::Vec3DMetadata, openvdb::Vec3d>(grid, "gvr_spacing_mm").value_or(openvdb::Vec3d(1.0));
    m.valueMin = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_value_min").value_or(0);
    m.valueMax = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_value_max").value_or(0);
    m.background = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_background").value_or(0);
    m.threshold = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_threshold");
    m.thresholdAbove = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_threshold_above");
    m.padding = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_padding_value");
    m.paddingVoxels =
        std::uint64_t(findMeta<openvdb::Int64Metadata, std::int64_t>(grid, "gvr_padding_voxels").value_or(0));
    m.markedPadding = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_marked_padding");
    m.roundedVoxels =
        std::uint64_t(findMeta<openvdb::Int64Metadata, std::int64_t>(grid, "gvr_rounded_voxels").value_or(0));
    m.storedSlope = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_stored_slope").value_or(1.0);
    m.storedIntercept = findMeta<openvdb::DoubleMetadata, double>(grid, "gvr_stored_intercept").value_or(0.0);
    if (auto codes = findMeta<openvdb::Vec3IMetadata, openvdb::Vec3i>(grid, "gvr_nifti_codes")) {
        m.niftiCodes = NiftiCodes{codes->x(), codes->y(), codes->z()};
    }
    return m;
}

}  // namespace gvr
