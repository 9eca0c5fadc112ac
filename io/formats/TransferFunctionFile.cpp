#include "io/formats/TransferFunctionFile.h"

#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "io/guard/InputFile.h"
#include "pipeline/Error.h"

#include <nlohmann/json.hpp>

#include <fstream>

namespace gvr {

TransferFunction readTransferFunction(const std::string& path) {
    requireRegularFile(path);
    std::ifstream in(path);
    if (!in) throw InputError(path, "cannot open the transfer function file");
    const nlohmann::json file = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (file.is_discarded()) throw InputError(path, "not valid JSON");
    if (!file.is_object() || !file.contains("points") || !file["points"].is_array()) {
        throw InputError(path, "expected {\"points\": [[value, r, g, b, a], ...]}");
    }
    std::vector<TransferPoint> points;
    for (const nlohmann::json& entry : file["points"]) {
        if (!entry.is_array() || entry.size() != 5 ||
            !std::all_of(entry.begin(), entry.end(), [](const nlohmann::json& v) { return v.is_number(); })) {
            throw InputError(
                path, "point " + std::to_string(points.size()) + " is not [value, r, g, b, a] with five numbers");
        }
        TransferPoint point;
        point.value = entry[0].get<double>();
        for (int c = 0; c < 4; ++c) {
            // Checked as a double: a float cast of 1e300 is undefined behaviour.
            const double channel = entry[c + 1].get<double>();
            if (!(channel >= 0.0 && channel <= 1.0)) {
                throw InputError(path,
                                 "point " + std::to_string(points.size()) + ": colour and opacity must lie in [0, 1]");
            }
            point.rgba[c] = float(channel);
        }
        points.push_back(point);
    }
    return TransferFunction(std::move(points), path);
}

void writeTransferFunction(const std::string& path, const TransferFunction& tf) {
    nlohmann::json points = nlohmann::json::array();
    for (const TransferPoint& p : tf.points()) points.push_back({p.value, p.rgba[0], p.rgba[1], p.rgba[2], p.rgba[3]});
    writeAtomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary);
        out << jsonText({{"points", points}}) << "\n";
        if (!out.flush()) throw InputError(path, "cannot write the transfer function");
    });
}

}  // namespace gvr
