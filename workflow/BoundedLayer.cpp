#include "workflow/BoundedLayer.h"

#include "io/AssetExport.h"
#include "io/AssetFile.h"
#include "io/AssetResidual.h"
#include "pipeline/Error.h"
#include "pipeline/QualityMetrics.h"
#include "pipeline/ResidualLayer.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace gvr {

double parseMaxError(const std::string& text, double dataRange) {
    const bool relative = !text.empty() && text.back() == '%';
    const std::string number = relative ? text.substr(0, text.size() - 1) : text;
    std::size_t used = 0;
    double value = NAN;
    try {
        value = std::stod(number, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != number.size()) {
        throw InputError("`max_error`", "'" + text + "' is not a number (of the source's units, or a percentage of "
                                        "its data range such as 0.5%)");
    }
    return relative ? value / 100.0 * dataRange : value;
}

void checkBoundBeforeFit(double bound, const std::string& name) {
    if (!(bound >= 0.0) || !std::isfinite(bound)) {
        throw InputError(name, "must be a finite number at least 0 (or a percentage of the data range)");
    }
}

std::string addErrorBound(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                          double bound, BoundedLayerReport& report, const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    const GaussianAsset asset = decodeAsset(assetBytes, name);
    const openvdb::Vec3i dims = asset.source.dims;
    if (source.dims != openvdb::Coord(dims.x(), dims.y(), dims.z()) || source.channels != asset.params.channels) {
        throw InputError(name, "the source as read is not on the asset's lattice, so no residual layer can be "
                               "placed on it");
    }
    const FloatVolume prediction = gaussianPrediction(asset, progress);
    const bool grey = asset.params.channels == 1;
    const ResidualDomain domain =
        residualDomainOf(source, grey ? asset.source.storedSlope : 1.0, grey ? asset.source.storedIntercept : 0.0);
    ResidualLayer layer = encodeResidualLayer(source, prediction, bound, domain);
    const FloatVolume reconstruction = decodeResidualLayer(layer, prediction);
    report.maxError = maxAbsoluteError(source, reconstruction);
    if (!(report.maxError <= bound)) throw std::logic_error("the residual layer missed its own bound");
    layer.reconstructionChecksum = reconstructionChecksum(reconstruction);
    std::string bytes = withResidualLayer(assetBytes, layer);
    report.bound = bound;
    report.integers = domain.integers;
    report.exactVoxels = layer.exactVoxels();
    report.gaussianBytes = assetBytes.size();
    report.fileBytes = bytes.size();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bytes;
}

}  // namespace gvr
