// gvr probe ASSET --world X,Y,Z | --index I,J,K: what the Gaussian field holds at given points.

#include "cli/Commands.h"
#include "cli/LayersOption.h"
#include "io/asset/AssetFile.h"
#include "io/formats/JsonText.h"
#include "pipeline/Error.h"
#include "workflow/ProbeAsset.h"

#include <iomanip>
#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct ProbeFlags {
    std::string input;
    std::vector<std::string> indexPoints, worldPoints;
    std::string layers = "all";
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
std::vector<std::array<double, 3>> indexPointsOf(const ProbeFlags& flags, const GaussianAsset& asset) {
    if (flags.indexPoints.empty() && flags.worldPoints.empty()) {
        throw InputError("probe", "give points with --world X,Y,Z (mm) or --index I,J,K");
    }
    const openvdb::math::Mat4d indexFromWorld = asset.worldFromIndex.inverse();
    std::vector<std::array<double, 3>> points;
    const auto add = [&](const openvdb::Vec3d& p) { points.push_back({p[0], p[1], p[2]}); };
    for (const std::string& text : flags.worldPoints) add(indexFromWorld.transform(parsePoint("--world", text)));
    for (const std::string& text : flags.indexPoints) add(parsePoint("--index", text));
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
    const AssetLayers layers = parseAssetLayers(flags.layers, "--layers");
    const std::vector<std::array<double, 3>> points = indexPointsOf(flags, asset);
    const std::vector<AssetProbe::Sample> samples = probeAsset(asset, points, layers, flags.input);
    const int channels = asset.params.channels;
    const bool bounded = readsResidualLayer(asset, layers);
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t n = 0; n < points.size(); ++n) {
        const openvdb::Vec3d world = asset.worldFromIndex.transform(openvdb::Vec3d(points[n].data()));
        rows.push_back({{"index", points[n]},
                        {"world_mm", {world[0], world[1], world[2]}},
                        {"value", std::vector<double>(samples[n].value.begin(), samples[n].value.begin() + channels)},
                        {"gaussians", samples[n].gaussians}});
    }
    if (flags.json) {
        std::cout << jsonText({{"asset", flags.input},
                               {"layers", flags.layers},
                               {"max_error", bounded ? nlohmann::json(asset.residual->bound) : nlohmann::json()},
                               {"points", rows}},
                              2)
                  << "\n";
        return;
    }
    const std::string from = bounded ? " Gaussians and the residual layer\n" : " Gaussians\n";
    for (const auto& row : rows) {
        std::cout << "world " << triple(row["world_mm"]) << " mm (index " << triple(row["index"])
                  << "): " << valuesText(row["value"]) << " from " << row["gaussians"] << from;
    }
}

}  // namespace

void addProbeCommand(CLI::App& app) {
    auto flags = std::make_shared<ProbeFlags>();
    CLI::App* command =
        app.add_subcommand("probe",
                           "Evaluate a Gaussian asset at points given in world millimetres (or source voxel indices), "
                           "in the source's physical units");
    command->add_option("asset", flags->input, "Gaussian asset from gvr fit")->required();
    command
        ->add_option("--world", flags->worldPoints,
                     "A point X,Y,Z in world millimetres, the source's scanner space (repeatable)")
        ->allow_extra_args(false);
    command->add_option("--index", flags->indexPoints, "A point I,J,K in source voxel indices (repeatable)")
        ->allow_extra_args(false);
    addLayersOption(*command, flags->layers, "at its voxel centres, trilinear between them");
    command->add_flag("--json", flags->json, "Print the values as JSON");
    command->callback([flags] { runProbe(*flags); });
}

}  // namespace gvr
