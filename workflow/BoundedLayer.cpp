#include "workflow/BoundedLayer.h"

#include "io/asset/AssetExport.h"
#include "io/asset/AssetFile.h"
#include "io/asset/AssetResidual.h"
#include "pipeline/Error.h"
#include "pipeline/QualityMetrics.h"
#include "pipeline/ResidualLayer.h"
#include "workflow/BoundSearch.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <optional>
#include <sstream>
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
        throw InputError("`max_error`", "'" + text +
                                            "' is not a number (of the source's units, or a percentage of "
                                            "its data range such as 0.5%)");
    }
    return relative ? value / 100.0 * dataRange : value;
}

BoundRequest BoundRequest::exactly(double bound, double ratio) {
    std::ostringstream text;
    text << std::setprecision(17) << bound;  // 17 digits: the double, exactly
    return {text.str(), ratio};
}

double BoundRequest::gaussianRatio() const {
    if (searched()) return std::max(kBoundedPreviewRatio, 4.0 * ratio);
    return ratio > 0.0 ? ratio : kBoundedPreviewRatio;
}

void BoundRequest::applyTo(BudgetedFitOptions& options) const {
    if (options.gaussians > 0) return;
    options.ratio = gaussianRatio();
    options.minimumGaussians = kBoundedPreviewGaussians;
}

void checkBoundRequest(const BoundRequest& request, const std::string& maxErrorName, const std::string& ratioName) {
    if (request.searched()) {
        if (request.ratio > 0.0) return;
        throw InputError(maxErrorName, std::string(kSearchedBound) + " searches the bound for " + ratioName +
                                           ", the ratio the whole asset must fit; give one");
    }
    const double bound = parseMaxError(request.maxError, 1.0);
    if (!(bound >= 0.0) || !std::isfinite(bound)) {
        throw InputError(maxErrorName, "must be a finite number at least 0 (or a percentage of the data range, or " +
                                           std::string(kSearchedBound) + " with a ratio)");
    }
}

namespace {

/// What every layer over one fit is encoded over: the Gaussians on the source's
/// lattice, and the numbers the source's voxels are.
struct Prediction {
    FloatVolume values;
    ResidualDomain domain;
    double dataRange = 0.0;  ///< the source's, as its metadata says: what a percentage bound is of
    double largestMagnitude = 0.0;
    double rawSourceBytes = 0.0;
};

Prediction predictionOf(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                        const ProgressFn& progress) {
    const GaussianAsset asset = decodeAsset(assetBytes, name);
    const openvdb::Vec3i dims = asset.source.dims;
    if (source.dims != openvdb::Coord(dims.x(), dims.y(), dims.z()) || source.channels != asset.params.channels) {
        throw InputError(name,
                         "the source as read is not on the asset's lattice, so no residual layer can be "
                         "placed on it");
    }
    const bool grey = asset.params.channels == 1;
    return {gaussianPrediction(asset, progress),
            residualDomainOf(source, grey ? asset.source.storedSlope : 1.0, grey ? asset.source.storedIntercept : 0.0),
            asset.source.valueMax - asset.source.valueMin,
            std::max(std::abs(asset.source.valueMin), std::abs(asset.source.valueMax)),
            double(asset.source.rawSourceBytes())};
}

/// What rounding two samples to float may add to their difference: nothing where
/// every sample is a whole number that a float holds, else two units in the last place
/// of the largest value, one for each sample's rounding however its reader computed it
/// (a CT's slope of 7.1098 HU left 90,000 voxels of a gantry-tilt
/// scan stored exactly at a bound of exactly two samples).
double roundingOfSamples(const ResidualDomain& domain, double largestMagnitude) {
    const bool whole = domain.slope == std::round(domain.slope) && domain.intercept == std::round(domain.intercept);
    if (whole && largestMagnitude < double(1 << 24)) return 0.0;
    const float largest = float(largestMagnitude);
    return 2.0 * (double(std::nextafter(largest, INFINITY)) - double(largest));
}

BoundLadder ladderOf(const Prediction& prediction) {
    const double range = prediction.dataRange;
    if (prediction.domain.integers) {
        return BoundLadder::wholeSamples(std::abs(prediction.domain.slope), range,
                                         roundingOfSamples(prediction.domain, prediction.largestMagnitude));
    }
    return BoundLadder::values(range > 0.0 ? range : 1.0);  // a constant volume: any bound holds it
}

/// The smallest bound with which the file fits @a ratio of the raw source.
double searchedBound(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                     const Prediction& prediction, double ratio, BoundedLayerReport& report) {
    const std::uint64_t maxBytes = std::uint64_t(prediction.rawSourceBytes / ratio);
    const auto fileBytes = [&](double bound) -> std::uint64_t {
        ResidualLayer layer = encodeResidualLayer(source, prediction.values, bound, prediction.domain);
        layer.reconstructionChecksum = UINT32_MAX;  // its widest: the file written is never larger
        return withResidualLayer(assetBytes, layer).size();
    };
    const std::optional<SearchedBound> found = smallestBoundWithin(ladderOf(prediction), maxBytes, fileBytes);
    if (!found) {
        std::ostringstream message;
        message << "no error bound fits " << ratio << ":1 (" << maxBytes << " bytes): the Gaussians and the "
                << "coarsest layer take more; ask a smaller ratio";
        throw InputError(name, message.str());
    }
    report.searchedRatio = ratio;
    report.encodes = found->encodes + 1;  // and the layer kept, encoded once more
    return found->bound;
}

}  // namespace

std::string addErrorBound(std::string_view assetBytes, const std::string& name, const FloatVolume& source,
                          const BoundRequest& request, BoundedLayerReport& report, const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    const Prediction prediction = predictionOf(assetBytes, name, source, progress);
    const double bound = request.searched() ? searchedBound(assetBytes, name, source, prediction, request.ratio, report)
                                            : parseMaxError(request.maxError, prediction.dataRange);
    ResidualLayer layer = encodeResidualLayer(source, prediction.values, bound, prediction.domain);
    const FloatVolume reconstruction = decodeResidualLayer(layer, prediction.values);
    report.maxError = maxAbsoluteError(source, reconstruction);
    if (!(report.maxError <= bound)) throw std::logic_error("the residual layer missed its own bound");
    layer.reconstructionChecksum = reconstructionChecksum(reconstruction);
    std::string bytes = withResidualLayer(assetBytes, layer);
    report.bound = bound;
    report.integers = prediction.domain.integers;
    report.exactVoxels = layer.exactVoxels();
    report.gaussianBytes = assetBytes.size();
    report.fileBytes = bytes.size();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return bytes;
}

}  // namespace gvr
