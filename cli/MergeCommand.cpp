// gvr merge PARTS... -o ASSET: the parts of a bricked fit (gvr fit --brick I --of N) as one asset.

#include "cli/Commands.h"
#include "cli/GridSummary.h"
#include "io/asset/AssetFile.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "workflow/BrickedFit.h"

#include <filesystem>
#include <iostream>

namespace gvr {

namespace {

struct MergeFlags {
    std::vector<std::string> parts;
    std::string output;
    bool json = false;
};

void runMerge(const MergeFlags& flags) {
    checkOutputPath("-o", flags.output, flags.parts);
    std::vector<GaussianAsset> parts;
    for (const std::string& path : flags.parts) parts.push_back(readAsset(path));
    std::size_t dropped = 0;
    GaussianAsset asset = mergeBrickParts(std::move(parts), flags.parts, &dropped);
    writeAsset(flags.output, asset);
    const std::uint64_t fileBytes = std::filesystem::file_size(flags.output);
    if (flags.json) {
        const nlohmann::json report{{"output", flags.output},
                                    {"parts", flags.parts.size()},
                                    {"gaussians", asset.params.count()},
                                    {"file_bytes", fileBytes},
                                    {"dropped_to_fit_budget", dropped}};
        std::cout << jsonText(report, 2) << "\n";
        return;
    }
    std::cout << "wrote " << flags.output << ": " << asset.params.count() << " Gaussians from " << flags.parts.size()
              << " bricks, " << formatBytes(fileBytes) << " (" << dropped << " dropped to fit the byte budget)\n";
}

}  // namespace

void addMergeCommand(CLI::App& app) {
    auto flags = std::make_shared<MergeFlags>();
    CLI::App* command = app.add_subcommand(
        "merge",
        "Join the parts that gvr fit --brick I --of N wrote (one per brick, any order) into one asset, "
        "trimmed to the fit's byte budget: the same asset, byte for byte, as gvr fit --bricks N");
    command->add_option("parts", flags->parts, "Part assets, one per brick")->required()->check(CLI::ExistingFile);
    command->add_option("-o,--output", flags->output, "Asset file to write")->required();
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->callback([flags] { runMerge(*flags); });
}

}  // namespace gvr
