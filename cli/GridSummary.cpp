#include "cli/GridSummary.h"

#include "io/asset/AssetExport.h"
#include "io/formats/JsonText.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace gvr {

namespace {

struct ActiveRange {
    double min = INFINITY, max = -INFINITY;

    template <typename GridT>
    void operator()(const GridT& grid) {
        for (auto value = grid.cbeginValueOn(); value; ++value) {
            if constexpr (openvdb::VecTraits<typename GridT::ValueType>::IsVec) {
                for (int c = 0; c < openvdb::VecTraits<typename GridT::ValueType>::Size; ++c) {
                    include(double((*value)[c]));
                }
            } else {
                include(double(*value));
            }
        }
    }

    void include(double v) {
        min = std::min(min, v);
        max = std::max(max, v);
    }
};

std::string fixed(double value, int digits) {
    std::ostringstream out;
    out << std::setprecision(digits) << value;
    return out.str();
}

}  // namespace

std::string formatBytes(std::uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double size = double(bytes);
    int unit = 0;
    while (size >= 1024.0 && unit < 4) {
        size /= 1024.0;
        ++unit;
    }
    return fixed(size, unit == 0 ? 6 : 3) + " " + units[unit];
}

namespace {

template <typename VecT>
nlohmann::json vectorJson(const VecT& v) {
    return nlohmann::json::array({v[0], v[1], v[2]});
}

/// One metadata value as JSON: numbers, booleans, strings and 3-vectors typed,
/// anything else as OpenVDB prints it.
nlohmann::json metadataValue(const openvdb::Metadata& meta) {
    if (auto* v = dynamic_cast<const openvdb::StringMetadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::DoubleMetadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::FloatMetadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::Int32Metadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::Int64Metadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::BoolMetadata*>(&meta)) return v->value();
    if (auto* v = dynamic_cast<const openvdb::Vec3IMetadata*>(&meta)) return vectorJson(v->value());
    if (auto* v = dynamic_cast<const openvdb::Vec3DMetadata*>(&meta)) return vectorJson(v->value());
    if (auto* v = dynamic_cast<const openvdb::Vec3SMetadata*>(&meta)) return vectorJson(v->value());
    return meta.str();
}

/// Millimetres in one world unit of @a grid: 1000 for a DCC export's metres.
double millimetresPerUnit(const openvdb::GridBase& grid) {
    const auto units = grid.getMetadata<openvdb::StringMetadata>("gvr_units");
    return units && units->value() == kDccUnits ? 1000.0 : 1.0;
}

}  // namespace

GridSummary summarizeGrid(const openvdb::GridBase& grid) {
    GridSummary summary;
    summary.name = grid.getName();
    summary.valueType = grid.valueType();
    summary.gridClass = openvdb::GridBase::gridClassToString(grid.getGridClass());
    summary.dims = grid.evalActiveVoxelBoundingBox().dim();
    summary.spacingMm = grid.transform().voxelSize() * millimetresPerUnit(grid);
    summary.activeVoxels = grid.activeVoxelCount();
    summary.memoryBytes = grid.memUsage();
    ActiveRange range;
    using Supported =
        openvdb::TypeList<openvdb::FloatGrid, openvdb::DoubleGrid, openvdb::Int32Grid, openvdb::Vec3SGrid>;
    if (grid.apply<Supported>(range) && summary.activeVoxels > 0) {
        summary.valueMin = range.min;
        summary.valueMax = range.max;
    }
    for (auto meta = grid.beginMeta(); meta != grid.endMeta(); ++meta) {
        if (meta->first == "name" || meta->first == "class") continue;
        summary.metadata[meta->first] = metadataValue(*meta->second);
    }
    if (grid.transform().isLinear()) {
        const openvdb::math::Mat4d rows = grid.transform().baseMap()->getAffineMap()->getMat4();
        std::array<std::array<double, 4>, 4> affine{};
        for (int r = 0; r < 4; ++r) {
            for (int c = 0; c < 4; ++c) affine[r][c] = rows(c, r);  // OpenVDB's row-vector matrix, transposed
        }
        summary.affine = affine;
    }
    return summary;
}

nlohmann::json toJson(const GridSummary& s) {
    return {{"name", s.name},
            {"value_type", s.valueType},
            {"grid_class", s.gridClass},
            {"dims", {s.dims.x(), s.dims.y(), s.dims.z()}},
            {"spacing_mm", {s.spacingMm.x(), s.spacingMm.y(), s.spacingMm.z()}},
            {"value_min", s.valueMin},
            {"value_max", s.valueMax},
            {"active_voxels", s.activeVoxels},
            {"memory_bytes", s.memoryBytes},
            {"metadata", s.metadata},
            {"affine", s.affine ? nlohmann::json(*s.affine) : nlohmann::json()}};
}

std::string toText(const GridSummary& s) {
    std::ostringstream out;
    const double boxVoxels = double(s.dims.x()) * s.dims.y() * s.dims.z();
    out << "grid '" << s.name << "' (" << s.valueType << ", " << s.gridClass << ")\n"
        << "  dimensions:    " << s.dims.x() << " x " << s.dims.y() << " x " << s.dims.z()
        << " voxels (active bounding box)\n"
        << "  spacing:       " << fixed(s.spacingMm.x(), 6) << " x " << fixed(s.spacingMm.y(), 6) << " x "
        << fixed(s.spacingMm.z(), 6) << " mm\n"
        << "  value range:   " << fixed(s.valueMin, 6) << " .. " << fixed(s.valueMax, 6) << " (active voxels)\n"
        << "  active voxels: " << s.activeVoxels;
    if (boxVoxels > 0) out << " (" << fixed(100.0 * s.activeVoxels / boxVoxels, 3) << " % of the box)";
    out << "\n  memory:        " << formatBytes(s.memoryBytes) << "\n";
    if (!s.metadata.empty()) out << "  metadata:\n";
    for (const auto& [key, value] : s.metadata.items()) {
        out << "    " << key << " = " << (value.is_string() ? value.get<std::string>() : jsonText(value)) << "\n";
    }
    return out.str();
}

}  // namespace gvr
