#include "cli/LayersOption.h"

namespace gvr {

CLI::Option* addLayersOption(CLI::App& command, std::string& layers, const std::string& where) {
    return command
        .add_option("--layers", layers,
                    "all: the Gaussians with the residual layer of fit --max-error, when the asset has one (every "
                    "voxel within its bound of the source, " +
                        where + "); gaussians: the Gaussians alone, the preview")
        ->check(CLI::IsMember({"all", "gaussians"}))
        ->capture_default_str();
}

}  // namespace gvr
