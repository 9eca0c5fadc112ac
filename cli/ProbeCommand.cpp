// gvr probe ASSET --world X,Y,Z | --index I,J,K: what the Gaussian field holds at given points.

#include "cli/Commands.h"
#include "io/AssetFile.h"
#include "io/JsonText.h"
#include "pipeline/AssetProbe.h"
#include "pipeline/Error.h"

#include <iomanip>
#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct ProbeFlags {
    std::string input;
    std::vector<std::string> indexPoints, worldPoints;
    bool json = false;
};

openvdb::Vec3d parsePoint(const std::string& flag, const std::string& text) {
    std::istringstream in(text);
    openvdb::Vec3d point;
    char comma1 = 0, comma2 = 0;
    if (!(in >> point[0] >> comma1 >> point[1] >> comma2 >> point[2]) || comma1 != ',' || comma2 != ',' ||
        !(in >> std::ws).eof() || !std::isfinite(point[0] + point[1] + point[2])) {
        throw InputError(flag, "'" + text + "' is not three numbers separated by commas");
    }
    return point;
}

/// Every point asked for, in the asset's index space: --world ones first.
std::vector<openvdb::Vec3d> indexPointsOf(const ProbeFlags& flags, const GaussianAsset& asset) {
    if (flags.indexPoints.empty() && flags.worldPoints.empty()) {
        throw InputError("probe", "give points with --world X,Y,Z (mm) or --index I,J,K");
    }
    const openvdb::math::Mat4d indexFromWorld = asset.worldFromIndex.inverse();
    std::vector<openvdb::Vec3d> points;
    for (const std::string& text : flags.worldPoints) points.push_back(indexFromWorld.transform(parsePoint("--world", text)));
    for (const std::string& text : flags.indexPoints) points.push_back(parsePoint("--index", text));
    return points;
}

/// "[12.50, -3.00, 40.25]": millimetres and voxel indices to a hundredth.
std::string triple(const nlohmann::json& values) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(2) << "[" << values[0].get<double>() << ", " << values[1].get<double>()
        << ", " << values[2].get<double>() << "]";
    return out.str();
}

/// Values to six significant digits, as the source's units deserve.
std::string valuesText(const nlohmann::json& values) {
    std::ostringstream out;
    out << std::setprecision(6);
    for (std::size_t c = 0; c < values.size(); ++c) out << (c ? ", " : "") << values[c].get<double>();
    return out.str();
}

void runProbe(const ProbeFlags& flags) {
    const GaussianAsset asset = readAsset(flags.input);
    AssetProbe probe(asset);
    nlohmann::json rows = nlohmann::json::array();
    for (const openvdb::Vec3d& index : indexPointsOf(flags, asset)) {
        const AssetProbe::Sample sample = probe.at({index[0], index[1], index[2]});
        const openvdb::Vec3d world = asset.worldFromIndex.transform(index);
        rows.push_back({{"index", {index[0], index[1], index[2]}},
                        {"world_mm", {world[0], world[1], world[2]}},
                        {"value", std::vector<double>(sample.value.begin(), sample.value.begin() + probe.channels())},
                        {"gaussians", sample.gaussians}});
    }
    if (flags.json) {
        std::cout << jsonText({{"asset", flags.input}, {"points", rows}}, 2) << "\n";
        return;
    }
    for (const auto& row : rows) {
        std::cout << "world " << triple(row["world_mm"]) << " mm (index " << triple(row["index"])
                  << "): " << valuesText(row["value"]) << " from " << row["gaussians"] << " Gaussians\n";
    }
}

}  // namespace

void addProbeCommand(CLI::App& app) {
    auto flags = std::make_shared<ProbeFlags>();
    CLI::App* command = app.add_subcommand(
        "probe", "Evaluate a Gaussian asset at points given in world millimetres (or source voxel indices), "
                 "in the source's physical units");
    command->add_option("asset", flags->input, "Gaussian asset from gvr fit")->required();
    command->add_option("--world", flags->worldPoints,
                        "A point X,Y,Z in world millimetres, the source's scanner space (repeatable)")
        ->allow_extra_args(false);
    command->add_option("--index", flags->indexPoints, "A point I,J,K in source voxel indices (repeatable)")
        ->allow_extra_args(false);
    command->add_flag("--json", flags->json, "Print the values as JSON");
    command->callback([flags] { runProbe(*flags); });
}

}  // namespace gvr
