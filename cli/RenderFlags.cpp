#include "cli/RenderFlags.h"

#include "pipeline/Error.h"
#include "render/Camera.h"

#include <sstream>

namespace gvr {

void addStackFlags(CLI::App& command, ShearWarpSettings& settings, bool* automatic) {
    if (automatic) *automatic = true;
    const std::string axesAndView =
        "axes: slice stacks across the world axis nearest the view, each built once and kept "
        "(an orbit builds two or three); view: a stack across the view, rebuilt beyond --reuse-angle";
    // By name only: an enum option would also take its numbers, "--stacks 1" for view.
    command
        .add_option_function<std::string>(
            "--stacks",
            [&settings, automatic](const std::string& name) {
                if (automatic) *automatic = name == "auto";
                settings.stacks = name == "view" ? StackOrientation::View : StackOrientation::Axes;
            },
            automatic ? "auto: view for a single image, axes for an orbit; " + axesAndView : axesAndView)
        ->check(automatic ? CLI::IsMember({"auto", "axes", "view"}) : CLI::IsMember({"axes", "view"}))
        ->type_name(automatic ? "auto|axes|view" : "axes|view")
        ->default_str(automatic ? "auto" : "axes");
    command
        .add_option("--reuse-angle", settings.reuseAngleDeg,
                    "With --stacks view: reuse the stack while the view is within this many degrees")
        ->capture_default_str();
    command
        .add_option("--supersample", settings.supersampling,
                    "Stack samples along each side of an image pixel (of a voxel, zoomed in), 1 to 4, averaged "
                    "over each pixel by the warp: 1.5 anti-aliases (on grids, past the one-ray ray marcher); 1 is "
                    "up to about twice as fast. Never coarser than the voxels, where the view shrinks the volume")
        ->capture_default_str();
    command
        .add_option_function<std::string>(
            "--classify",
            [&settings](const std::string& name) { settings.classification = *classificationNamed(name); },
            "How a grey volume's values take the transfer function: segments pre-integrates each stretch of a ray "
            "between two slices, so that bands of it thinner than a slice are seen; points classifies each sample "
            "alone, as the ray marcher does, and may miss them")
        ->check(CLI::IsMember({"points", "segments"}))
        ->type_name("points|segments")
        ->default_str(classificationName(ShearWarpSettings{}.classification));
}

std::pair<int, int> parseImageSize(const std::string& text) {
    int width = 0, height = 0;
    char x = 0;
    std::istringstream in(text);
    if (!(in >> width >> x >> height) || x != 'x' || !(in >> std::ws).eof() || width < 1 || height < 1 ||
        width > kMaxImageSide || height > kMaxImageSide) {
        throw InputError("--size", "'" + text + "' is not WIDTHxHEIGHT of 1 to " + std::to_string(kMaxImageSide) +
                                       " pixels each, e.g. 512x512");
    }
    return {width, height};
}

}  // namespace gvr
