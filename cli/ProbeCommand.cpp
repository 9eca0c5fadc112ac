// gvr probe ASSET --index I,J,K: what the Gaussian field holds at given points.

#include "AssetFile.h"
#include "AssetProbe.h"
#include "Commands.h"
#include "Error.h"

#include <iostream>
#include <sstream>

namespace gvr {

namespace {

struct ProbeFlags {
    std::string input;
    std::vector<std::string> points;
    bool json = false;
};

openvdb::Vec3d parsePoint(const std::string& text) {
    std::istringstream in(text);
    openvdb::Vec3d point;
    char comma1 = 0, comma2 = 0;
    if (!(in >> point[0] >> comma1 >> point[1] >> comma2 >> point[2]) || comma1 != ',' || comma2 != ',' ||
        !(in >> std::ws).eof() || !std::isfinite(point[0] + point[1] + point[2])) {
        throw InputError("--index", "'" + text + "' is not three numbers I,J,K");
    }
    return point;
}

void runProbe(const ProbeFlags& flags) {
    const GaussianAsset asset = readAsset(flags.input);
    AssetProbe probe(asset);
    nlohmann::json rows = nlohmann::json::array();
    for (const std::string& text : flags.points) {
        const openvdb::Vec3d index = parsePoint(text);
        const AssetProbe::Sample sample = probe.at({index[0], index[1], index[2]});
        const openvdb::Vec3d world = asset.worldFromIndex.transform(index);
        rows.push_back({{"index", {index[0], index[1], index[2]}},
                        {"world_mm", {world[0], world[1], world[2]}},
                        {"value", std::vector<double>(sample.value.begin(), sample.value.begin() + probe.channels())},
                        {"gaussians", sample.gaussians}});
    }
    if (flags.json) {
        std::cout << nlohmann::json{{"asset", flags.input}, {"points", rows}}.dump(2) << "\n";
        return;
    }
    for (const auto& row : rows) {
        std::cout << "index " << row["index"].dump() << " (world " << row["world_mm"].dump() << " mm): "
                  << row["value"].dump() << " from " << row["gaussians"] << " Gaussians\n";
    }
}

}  // namespace

void addProbeCommand(CLI::App& app) {
    auto flags = std::make_shared<ProbeFlags>();
    CLI::App* command = app.add_subcommand(
        "probe", "Evaluate a Gaussian asset at points of the source's index space, in physical units");
    command->add_option("asset", flags->input, "Gaussian asset from gvr fit")->required();
    command->add_option("--index", flags->points, "A point I,J,K in source voxel indices (repeatable)")
        ->required()->allow_extra_args(false);
    command->add_flag("--json", flags->json, "Print the values as JSON");
    command->callback([flags] { runProbe(*flags); });
}

}  // namespace gvr
