#include "workflow/Evaluate.h"

#include "io/LabelGrid.h"
#include "io/asset/AssetFile.h"
#include "io/formats/FileKind.h"
#include "io/formats/GridFile.h"
#include "io/formats/ImageFile.h"
#include "pipeline/Error.h"
#include "pipeline/Fitter.h"
#include "pipeline/Luminance.h"
#include "workflow/ReportNumbers.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace gvr {

namespace {

std::string dimsText(const FloatVolume& v) {
    return std::to_string(v.dims.x()) + "x" + std::to_string(v.dims.y()) + "x" + std::to_string(v.dims.z()) + " with " +
           std::to_string(v.channels) + " channel(s)";
}

/// Brings @a test onto the reference's samples, or says why it cannot.
void matchGeometry(const std::string& testPath, bool resample, const ComparisonInput& reference,
                   ComparisonInput& test) {
    const FloatVolume& ref = reference.volume;
    FloatVolume& other = test.volume;
    if (reference.isImage != test.isImage) {
        throw InputError(testPath, "one input is a 2D image and the other a volume");
    }
    if (ref.channels != other.channels) {
        throw InputError(testPath, "has " + std::to_string(other.channels) + " channel(s), the reference " +
                                       std::to_string(ref.channels));
    }
    const bool sameDims = ref.dims == other.dims;
    const bool sameTransform = reference.isImage || samePlacement(ref.worldFromIndex, other.worldFromIndex, 1e-5);
    if (sameDims && sameTransform) return;
    if (!resample || reference.isImage) {
        throw InputError(testPath,
                         (sameDims ? std::string("is placed differently in the world than the reference")
                                   : "is " + dimsText(other) + ", the reference " + dimsText(ref)) +
                             (reference.isImage ? "" : "; pass `resample` to resample it onto the reference"));
    }
    other = resampleTrilinear(other, ref.dims, ref.worldFromIndex);
}

/// The voxels that count as foreground, and how they were chosen.
std::vector<std::uint8_t> foregroundMask(const EvalOptions& options, const ComparisonInput& reference,
                                         std::string& rule) {
    const FloatVolume& ref = reference.volume;
    std::vector<std::uint8_t> mask(ref.voxelCount(), 0);
    if (!options.mask.empty()) {
        const ComparisonInput m = loadComparisonInput(options.mask, options.ingest);
        if (m.volume.dims != ref.dims) {
            throw InputError(options.mask, "mask is " + dimsText(m.volume) + ", the reference " + dimsText(ref));
        }
        for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = m.volume.values[n * m.volume.channels] != 0.0f;
        rule = "inside the mask " + options.mask;
        return mask;
    }
    if (!options.threshold && !ref.foreground.empty()) {
        rule = reference.foregroundRule;
        return ref.foreground;
    }
    const auto key = [&](std::size_t n) { return sampleKey(ref.values.data() + n * ref.channels, ref.channels); };
    double cut = 0.0;
    if (options.threshold) {
        if (std::isnan(*options.threshold)) throw InputError("`threshold`", "must be a number, not NaN");
        cut = *options.threshold;
        rule = "reference above " + std::to_string(cut);
    } else {
        cut = INFINITY;
        for (std::size_t n = 0; n < mask.size(); ++n) cut = std::min(cut, key(n));
        rule = "reference above its minimum";
    }
    for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = key(n) > cut;
    return mask;
}

/// The label of each reference voxel: the label grid's voxel at the same place.
std::vector<int> labelsOnSamples(const FloatVolume& ref, const openvdb::Int32Grid& labels) {
    std::vector<int> out(ref.voxelCount());
    auto accessor = labels.getConstAccessor();
    for (int k = 0; k < ref.dims.z(); ++k) {
        for (int j = 0; j < ref.dims.y(); ++j) {
            for (int i = 0; i < ref.dims.x(); ++i) {
                const openvdb::Vec3d world = ref.worldFromIndex.transform(openvdb::Vec3d(i, j, k));
                const openvdb::Coord at = openvdb::Coord::round(labels.transform().worldToIndex(world));
                out[ref.indexOf(i, j, k)] = accessor.getValue(at);
            }
        }
    }
    return out;
}

/// Per-structure quality over the labels of --labels: the structures --structures
/// names, else those of a labelled test asset, else all.
void evaluateStructures(const EvalOptions& options, const openvdb::Int32Grid& labels, const FloatVolume& ref,
                        const FloatVolume& test, EvalResult& e) {
    e.labelTable = labelTableOf(labels);
    const std::string spec = options.structures.empty() ? "all" : options.structures;
    const std::vector<int> ids =
        selectLabels(e.labelTable, spec, options.structures.empty() ? options.labels : "`structures`");
    e.structures = structureQuality(ref, test, labelsOnSamples(ref, labels), ids, e.peak);
}

/// The label grid that ingest --labels stored in the .vdb options.labels, or any
/// label volume ingest reads, placed onto @a reference's voxels (nearest neighbour
/// when its lattice differs: eval maps voxels by world position anyway).
openvdb::Int32Grid::Ptr loadLabelGrid(const EvalOptions& options, const ComparisonInput& reference) {
    if (fileKind(options.labels) == FileKind::Vdb) return findLabelGrid(*readGridFile(options.labels), options.labels);
    if (!reference.grid) throw InputError(options.labels, "labels apply to volumes, not to 2D images");
    IngestOptions atlas = options.ingest;
    atlas.labels = options.labels;
    atlas.labelNames = options.labelNames;
    atlas.resampleLabels = true;
    return readLabels(atlas, *reference.grid);
}

/// The structures of a labelled asset at @a path, as a --structures list; else "".
std::string assetStructures(const std::string& path) {
    if (fileKind(path) != FileKind::Asset) return "";
    std::string spec;
    for (const auto& [id, name] : readAsset(path).labelTable.names)
        spec += (spec.empty() ? "" : ",") + std::to_string(id);
    return spec;
}

bool isRendering(const ComparisonInput& input) { return input.isImage && input.volume.channels == 4; }

/// Refuses a difference image that cannot be made, as soon as the reference is known.
void checkDifferenceRequest(const EvalOptions& options, const ComparisonInput& reference,
                            const std::string& referenceName) {
    if (!options.differenceImage.empty() && !isRendering(reference)) {
        throw InputError("`difference`", "needs two RGBA images (renderings); " + referenceName + " is not one");
    }
    if (!(options.differenceGain > 0.0f && std::isfinite(options.differenceGain))) {
        throw InputError("`difference_gain`", "must be a positive number");
    }
}

/// The voxels every measure counts (1 = counted), or empty for all.
std::vector<std::uint8_t> keptVoxels(const ComparisonInput& reference) {
    if (reference.excluded.empty()) return {};
    std::vector<std::uint8_t> kept(reference.excluded.size());
    for (std::size_t n = 0; n < kept.size(); ++n) kept[n] = !reference.excluded[n];
    return kept;
}

/// SSIM has no mask: the voxels left out get one value in both volumes, the lowest
/// the reference keeps, so they agree and no step to the padding shows in a window.
std::pair<FloatVolume, FloatVolume> withExcludedAlike(const ComparisonInput& reference, const FloatVolume& test) {
    FloatVolume a = reference.volume, b = test;
    float lowest = INFINITY;
    for (std::size_t n = 0; n < reference.excluded.size(); ++n) {
        if (!reference.excluded[n])
            lowest = std::min(
                lowest, *std::min_element(a.values.begin() + n * a.channels, a.values.begin() + (n + 1) * a.channels));
    }
    for (std::size_t n = 0; n < reference.excluded.size(); ++n) {
        if (!reference.excluded[n]) continue;
        std::fill_n(a.values.begin() + n * a.channels, a.channels, lowest);
        std::fill_n(b.values.begin() + n * b.channels, b.channels, lowest);
    }
    return {std::move(a), std::move(b)};
}

/// The comparison itself; @a labels (may be null) only with options.labels.
EvalResult compare(const ComparisonInput& reference, ComparisonInput test, const EvalOptions& options,
                   const openvdb::Int32Grid* labels, const std::string& referenceName, const std::string& testName) {
    const auto start = std::chrono::steady_clock::now();
    matchGeometry(testName, options.resample, reference, test);
    const bool renderings = isRendering(reference);
    EvalResult e;
    e.peak = options.peak.value_or(reference.dataRange);
    if (!(e.peak > 0.0) || !std::isfinite(e.peak)) {
        throw InputError(
            options.peak ? "`peak`" : referenceName,
            options.peak ? "must be a positive number" : "has no data range (a constant volume); give `peak`");
    }
    std::vector<std::uint8_t> mask = foregroundMask(options, reference, e.foregroundRule);
    const std::vector<std::uint8_t> kept = keptVoxels(reference);
    if (!kept.empty()) {
        for (std::size_t n = 0; n < mask.size(); ++n) mask[n] &= kept[n];
    }
    e.excludedVoxels = reference.excludedVoxels;
    e.referenceReadAs = reference.readAs;
    e.foregroundVoxels = std::size_t(std::count(mask.begin(), mask.end(), 1));
    e.mse = meanSquaredError(reference.volume, test.volume, kept);
    e.psnr = psnrFromMse(e.mse, e.peak);
    e.maxError = maxAbsoluteError(reference.volume, test.volume, kept);
    e.foregroundMse = meanSquaredError(reference.volume, test.volume, mask);
    e.foregroundPsnr = e.foregroundVoxels > 0 ? psnrFromMse(e.foregroundMse, e.peak) : NAN;
    SsimSettings ssimSettings;
    ssimSettings.dataRange = e.peak;
    const auto measureSsim = [&](const FloatVolume& a, const FloatVolume& b) {
        e.ssim = ssim(a, b, ssimSettings);
        e.msSsim = msSsim(a, b, ssimSettings);
    };
    if (reference.excluded.empty()) {
        measureSsim(reference.volume, test.volume);
    } else {  // copies, only where there is something to set apart
        const auto [a, b] = withExcludedAlike(reference, test.volume);
        measureSsim(a, b);
    }
    if (labels) evaluateStructures(options, *labels, reference.volume, test.volume, e);
    if (renderings) e.rendering = renderingQuality(reference.volume, test.volume);
    if (!options.differenceImage.empty()) {
        const FloatVolume difference = renderingDifference(reference.volume, test.volume, options.differenceGain);
        writeImage(options.differenceImage, difference.dims.x(), difference.dims.y(), difference.values.data());
    }
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return e;
}

}  // namespace

RenderingQuality renderingQuality(const FloatVolume& reference, const FloatVolume& test) {
    const RenderingError error = renderingError(reference, test);
    RenderingQuality q;
    q.coveredPixels = error.coveredPixels;
    q.psnrOverBlack = psnrFromMse(error.overBlack, 1.0);
    q.psnrOverWhite = psnrFromMse(error.overWhite, 1.0);
    q.psnr = psnrFromMse(0.5 * (error.overBlack + error.overWhite), 1.0);
    return q;
}

EvalResult evaluate(const ComparisonInput& reference, ComparisonInput test, const EvalOptions& options,
                    const std::string& referenceName, const std::string& testName) {
    checkDifferenceRequest(options, reference, referenceName);
    openvdb::Int32Grid::Ptr labels;
    if (!options.labels.empty()) labels = loadLabelGrid(options, reference);
    return compare(reference, std::move(test), options, labels.get(), referenceName, testName);
}

EvalResult evaluate(const std::string& referencePath, const std::string& testPath, const EvalOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    EvalOptions resolved = options;
    if (!options.labels.empty() && options.structures.empty()) resolved.structures = assetStructures(testPath);
    // The grids go as soon as they are sampled (the reference's once the labels are
    // on it): held with the samples, they would double eval's memory.
    ComparisonInput reference = loadComparisonInput(referencePath, options.ingest);
    checkDifferenceRequest(options, reference, referencePath);  // before the test is read
    openvdb::Int32Grid::Ptr labels;
    if (!options.labels.empty()) labels = loadLabelGrid(options, reference);
    reference.grid.reset();
    ComparisonInput test = loadComparisonInput(testPath, options.ingest);
    test.grid.reset();
    EvalResult e = compare(reference, std::move(test), resolved, labels.get(), referencePath, testPath);
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();  // reading included
    return e;
}

nlohmann::json evalResultJson(const EvalResult& e) {
    nlohmann::json out = {{"mse", e.mse},
                          {"psnr", jsonNumber(e.psnr)},
                          {"max_error", e.maxError},
                          {"fg_mse", e.foregroundVoxels ? nlohmann::json(e.foregroundMse) : nullptr},
                          {"fg_psnr", e.foregroundVoxels ? jsonNumber(e.foregroundPsnr) : nullptr},
                          {"fg_voxels", e.foregroundVoxels},
                          {"fg_rule", e.foregroundRule},
                          {"ssim", e.ssim},
                          {"ms_ssim", e.msSsim.value},
                          {"ms_ssim_scales", e.msSsim.scales},
                          {"peak", e.peak},
                          {"reference_read_as", e.referenceReadAs},
                          {"excluded_voxels", e.excludedVoxels},
                          {"seconds", e.seconds}};
    if (e.rendering) {
        out["rendering"] = {{"psnr", jsonNumber(e.rendering->psnr)},
                            {"psnr_over_black", jsonNumber(e.rendering->psnrOverBlack)},
                            {"psnr_over_white", jsonNumber(e.rendering->psnrOverWhite)},
                            {"covered_pixels", e.rendering->coveredPixels}};
    }
    for (const StructureQuality& q : e.structures) {
        out["structures"].push_back({{"id", q.id},
                                     {"name", e.labelTable.nameOf(q.id)},
                                     {"voxels", q.voxels},
                                     {"mse", q.mse},
                                     {"psnr", jsonNumber(q.psnr)},
                                     {"ssim", q.ssim}});
    }
    return out;
}

}  // namespace gvr
