#include "io/LabelGrid.h"

#include "io/formats/JsonText.h"
#include "io/guard/InputFile.h"
#include "pipeline/Error.h"
#include "pipeline/SampleType.h"
#include "pipeline/VolumeMetadata.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace gvr {

namespace {

constexpr const char* kNamesKey = "gvr_label_names";

/// Whether a whole number fits the 32-bit labels gvr keeps.
bool isInt32(double value) {
    return value >= std::numeric_limits<std::int32_t>::min() && value <= std::numeric_limits<std::int32_t>::max();
}

/// Label values in the file's own voxel order. @throw InputError for non-integers.
std::vector<std::int32_t> integerLabels(const DenseVolume& volume, const std::string& path) {
    if (volume.channels != 1)
        throw InputError(path, "a label volume must have one channel, not " + std::to_string(volume.channels));
    std::vector<std::int32_t> labels(volume.voxelCount());
    dispatchSampleType(volume.type, [&](auto sample) {
        using T = decltype(sample);
        const T* data = volume.data<T>();
        for (std::size_t n = 0; n < labels.size(); ++n) {
            const double value = volume.slope * double(data[n]) + volume.intercept;
            if (value != std::round(value)) {
                throw InputError(path, "is not a label volume: voxel " + std::to_string(n) + " holds " +
                                           std::to_string(value) + ", not an integer");
            }
            if (!isInt32(value)) {
                throw InputError(path, "voxel " + std::to_string(n) + " holds the label " + std::to_string(value) +
                                           ", beyond the 32-bit labels gvr keeps");
            }
            labels[n] = std::int32_t(value);
        }
    });
    return labels;
}

openvdb::math::Mat4d matrixOf(const openvdb::GridBase& grid) {
    return grid.transform().baseMap()->getAffineMap()->getMat4();
}

std::string describe(const std::array<std::int64_t, 3>& dims, const openvdb::math::Mat4d& m) {
    std::ostringstream text;
    text << dims[0] << "x" << dims[1] << "x" << dims[2] << " voxels of " << axisSpacing(m)
         << " mm with voxel (0,0,0) at " << m.row(3).getVec3() << " mm";
    return text.str();
}

/// The label under each image voxel: the label voxel whose centre is nearest.
std::int32_t nearestLabel(const std::vector<std::int32_t>& labels, const std::array<std::int64_t, 3>& dims,
                          const openvdb::math::Mat4d& labelFromWorld, const openvdb::Vec3d& world) {
    const openvdb::Vec3d index = labelFromWorld.transform(world);
    std::int64_t at[3];
    for (int a = 0; a < 3; ++a) {
        at[a] = std::int64_t(std::floor(index[a] + 0.5));
        if (at[a] < 0 || at[a] >= dims[a]) return 0;
    }
    return labels[std::size_t((at[2] * dims[1] + at[1]) * dims[0] + at[0])];
}

void storeNames(openvdb::GridBase& grid, const std::set<int>& present, const LabelTable& names) {
    nlohmann::json table = nlohmann::json::object();
    for (int id : present) table[std::to_string(id)] = names.nameOf(id);
    grid.insertMeta(kNamesKey, openvdb::StringMetadata(jsonText(table)));
}

}  // namespace

LabelTable readLabelNames(const std::string& path) {
    requireRegularFile(path);
    std::ifstream in(path);
    if (!in) throw InputError(path, "cannot open the label names");
    LabelTable table;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        // The names go into the grid's and the asset's JSON, which holds UTF-8 only.
        if (!isUtf8(line)) throw InputError(path, "line " + std::to_string(number) + " is not UTF-8 text");
        line = line.substr(0, line.find('#'));
        std::istringstream fields(line);
        std::string id, name;
        if (!(fields >> id)) continue;  // blank or comment
        char* end = nullptr;
        const long value = std::strtol(id.c_str(), &end, 10);
        if (*end != '\0' || !(fields >> name)) {
            throw InputError(path, "line " + std::to_string(number) + " is not \"ID NAME ...\": " + line);
        }
        if (!isInt32(double(value))) {
            throw InputError(
                path, "line " + std::to_string(number) + " names label " + id + ", beyond the 32-bit labels gvr keeps");
        }
        if (value != 0) table.names[int(value)] = name;
    }
    if (table.names.empty()) throw InputError(path, "names no label");
    return table;
}

openvdb::Int32Grid::Ptr buildLabelGrid(const std::string& path, const ReadOptions& options,
                                       const openvdb::GridBase& image, const LabelGridSettings& settings) {
    const DenseVolume volume = readVolume(path, options);
    const std::vector<std::int32_t> labels = integerLabels(volume, path);
    const std::optional<VolumeMetadata> metadata = readVolumeMetadata(image);
    if (!metadata) throw InputError(path, "labels need an image grid written by ingest");
    const std::array<std::int64_t, 3> imageDims{metadata->dims.x(), metadata->dims.y(), metadata->dims.z()};
    const openvdb::math::Mat4d imageMatrix = matrixOf(image);
    const bool sameLattice = volume.dims == imageDims && samePlacement(volume.worldFromIndex, imageMatrix, 1e-4);
    if (!sameLattice && !settings.resample) {
        throw InputError(path, "is " + describe(volume.dims, volume.worldFromIndex) + ", the image " +
                                   describe(imageDims, imageMatrix) +
                                   "; pass `resample_labels` to resample the labels (nearest neighbour)");
    }
    auto grid = openvdb::Int32Grid::create(0);
    grid->setName(kLabelGridName);
    grid->setTransform(image.transform().copy());
    auto accessor = grid->getAccessor();
    const openvdb::math::Mat4d labelFromWorld = volume.worldFromIndex.inverse();
    std::set<int> present;
    for (std::int64_t k = 0; k < imageDims[2]; ++k) {
        for (std::int64_t j = 0; j < imageDims[1]; ++j) {
            for (std::int64_t i = 0; i < imageDims[0]; ++i) {
                const std::int32_t label =
                    sameLattice ? labels[std::size_t((k * imageDims[1] + j) * imageDims[0] + i)]
                                : nearestLabel(labels, volume.dims, labelFromWorld,
                                               imageMatrix.transform(openvdb::Vec3d(double(i), double(j), double(k))));
                if (label == 0) continue;
                accessor.setValueOn(openvdb::Coord(int(i), int(j), int(k)), label);
                present.insert(label);
            }
        }
    }
    storeNames(*grid, present, settings.names);
    return grid;
}

LabelTable labelTableOf(const openvdb::GridBase& labels) {
    LabelTable table;
    const auto meta = labels.getMetadata<openvdb::StringMetadata>(kNamesKey);
    if (!meta) return table;
    const nlohmann::json names = nlohmann::json::parse(meta->value(), nullptr, false);
    if (!names.is_object()) return table;
    for (const auto& [id, name] : names.items()) {
        if (name.is_string()) table.names[std::atoi(id.c_str())] = name.get<std::string>();
    }
    return table;
}

openvdb::Int32Grid::Ptr storedLabelGrid(const openvdb::GridPtrVec& grids) {
    for (const auto& grid : grids) {
        if (grid->getName() == kLabelGridName && grid->isType<openvdb::Int32Grid>()) {
            return openvdb::gridPtrCast<openvdb::Int32Grid>(grid);
        }
    }
    return nullptr;
}

openvdb::Int32Grid::Ptr findLabelGrid(const openvdb::GridPtrVec& grids, const std::string& path) {
    if (openvdb::Int32Grid::Ptr labels = storedLabelGrid(grids)) return labels;
    throw InputError(path, "holds no label grid; ingest the image with `labels=LABELS`");
}

}  // namespace gvr
