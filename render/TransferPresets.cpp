#include "render/TransferPresets.h"

#include "pipeline/Error.h"

#include <algorithm>
#include <cmath>

namespace gvr {

namespace {

double percentile(std::vector<float> values, double fraction) {
    if (values.empty()) return 0.0;
    const std::size_t n = std::min(values.size() - 1, std::size_t(fraction * double(values.size() - 1) + 0.5));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(n), values.end());
    return values[n];
}

/// The values that are content: more than 2 % of the range away from the background,
/// so that faint tails over empty space (a Gaussian field's) do not shift the window.
std::vector<float> contentValues(const VolumeStatistics& statistics) {
    double reach = 0.0;
    for (float v : statistics.values) reach = std::max(reach, std::abs(v - statistics.background));
    std::vector<float> content;
    for (float v : statistics.values) {
        if (std::abs(v - statistics.background) > 0.02 * reach) content.push_back(v);
    }
    return content;
}

/// Points that must increase: a degenerate window (a constant volume) still gives one.
TransferFunction ramp(double from, double to, std::array<float, 4> low, std::array<float, 4> high,
                      const std::string& name) {
    if (!(to > from)) to = from + std::max(1e-6, std::abs(from) * 1e-6);
    return TransferFunction({{from, low}, {to, high}}, name);
}

}  // namespace

TransferFunction presetTransferFunction(const std::string& name, const VolumeStatistics& statistics) {
    if (name == "ct") {
        return TransferFunction({{-300.0, {0.60f, 0.30f, 0.20f, 0.0f}},
                                 {-50.0, {0.85f, 0.55f, 0.45f, 0.02f}},
                                 {150.0, {0.90f, 0.65f, 0.55f, 0.05f}},
                                 {300.0, {1.00f, 0.95f, 0.90f, 0.20f}},
                                 {1500.0, {1.00f, 1.00f, 1.00f, 0.60f}}},
                                name);
    }
    if (name == "ct-bone") {
        return TransferFunction({{150.0, {1.0f, 0.90f, 0.80f, 0.0f}},
                                 {400.0, {1.0f, 0.95f, 0.85f, 0.30f}},
                                 {1500.0, {1.0f, 1.00f, 1.00f, 0.80f}}},
                                name);
    }
    if (name == "mri") {
        const std::vector<float> content = contentValues(statistics);
        return ramp(percentile(content, 0.30), percentile(content, 0.995), {0, 0, 0, 0}, {1, 1, 1, 0.12f}, name);
    }
    if (name == "rgb") {
        const std::vector<float> content = contentValues(statistics);
        const double low = percentile(content, 0.02), high = percentile(content, 0.98);
        // Opacity grows away from the background: on white paper, dark is dense.
        if (std::abs(statistics.background - high) < std::abs(statistics.background - low)) {
            return ramp(low, high, {1, 1, 1, 0.25f}, {1, 1, 1, 0.0f}, name);
        }
        return ramp(low, high, {1, 1, 1, 0.0f}, {1, 1, 1, 0.25f}, name);
    }
    throw InputError("`tf` " + name,
                     "unknown transfer function; the presets are ct, ct-bone, mri and rgb, "
                     "or give a JSON file");
}

std::string defaultPreset(int channels, const VolumeStatistics& statistics) {
    if (channels == 3) return "rgb";
    return statistics.hounsfield ? "ct" : "mri";
}

bool presetTakes(const std::string& name, int channels) { return (name == "rgb") == (channels == 3); }

std::string presetMismatch(const std::string& name, int channels, const VolumeStatistics& statistics) {
    const std::string fits = defaultPreset(channels, statistics);
    if (!presetTakes(name, channels)) {
        return name + (channels == 3 ? " is for grey data, these are colour" : " is for colour data, these are grey") +
               "; " + fits + " fits them";
    }
    if ((name == "ct" || name == "ct-bone") && !statistics.hounsfield) {
        const auto [lo, hi] = std::minmax_element(statistics.values.begin(), statistics.values.end());
        std::string range;
        if (lo != statistics.values.end()) {
            range = " (" + std::to_string(int(std::floor(*lo))) + " to " + std::to_string(int(std::ceil(*hi))) + ")";
        }
        return name + " is in Hounsfield units, but these values never reach below -500" + range +
               ", so they are not CT in HU; " + fits + " fits them";
    }
    return "";
}

}  // namespace gvr
