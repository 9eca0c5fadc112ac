// gvr eval REFERENCE TEST: MSE, PSNR, foreground PSNR, SSIM and MS-SSIM.

#include "Commands.h"
#include "ComparisonInput.h"
#include "Error.h"
#include "Fitter.h"
#include "GaussianAsset.h"
#include "GridFile.h"
#include "LabelGrid.h"
#include "StructureQuality.h"
#include "Luminance.h"
#include "QualityMetrics.h"
#include "Report.h"
#include "SourceOptions.h"

#include <chrono>
#include <iomanip>
#include <iostream>

namespace gvr {

namespace {

struct EvalFlags {
    std::string reference, test, mask, labels, structures;
    std::optional<double> threshold, peak;
    bool resample = false, json = false;
    SourceFlags source;
};

struct Evaluation {
    double mse = 0, psnr = 0, foregroundMse = 0, foregroundPsnr = 0, ssim = 0, peak = 0, seconds = 0;
    std::size_t foregroundVoxels = 0;
    MsSsim msSsim;
    std::string foregroundRule;
    std::vector<StructureQuality> structures;
    LabelTable labelTable;
};

std::string dimsText(const FloatVolume& v) {
    return std::to_string(v.dims.x()) + "x" + std::to_string(v.dims.y()) + "x" + std::to_string(v.dims.z()) +
           " with " + std::to_string(v.channels) + " channel(s)";
}

/// Brings @a test onto the reference's samples, or says why it cannot.
void matchGeometry(const EvalFlags& flags, const ComparisonInput& reference, ComparisonInput& test) {
    const FloatVolume& ref = reference.volume;
    FloatVolume& other = test.volume;
    if (reference.isImage != test.isImage) {
        throw InputError(flags.test, "one input is a 2D image and the other a volume");
    }
    if (ref.channels != other.channels) {
        throw InputError(flags.test, "has " + std::to_string(other.channels) + " channel(s), the reference " +
                                         std::to_string(ref.channels));
    }
    const bool sameDims = ref.dims == other.dims;
    const bool sameTransform = reference.isImage || samePlacement(ref.worldFromIndex, other.worldFromIndex, 1e-5);
    if (sameDims && sameTransform) return;
    if (!flags.resample || reference.isImage) {
        throw InputError(flags.test, (sameDims ? std::string("is placed differently in the world than the reference")
                                               : "is " + dimsText(other) + ", the reference " + dimsText(ref)) +
                                         (reference.isImage ? "" : "; pass --resample to resample it onto the reference"));
    }
    other = resampleTrilinear(other, ref.dims, ref.worldFromIndex);
}

/// The voxels that count as foreground, and how they were chosen.
std::vector<std::uint8_t> foregroundMask(const EvalFlags& flags, const FloatVolume& ref,
                                         const IngestOptions& options, std::string& rule) {
    std::vector<std::uint8_t> mask(ref.voxelCount(), 0);
    if (!flags.mask.empty()) {
        const ComparisonInput m = loadComparisonInput(flags.mask, options);
        if (m.volume.dims != ref.dims) {
            throw InputError(flags.mask, "mask is " + dimsText(m.volume) + ", the reference " + dimsText(ref));
        }
        for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = m.volume.values[n * m.volume.channels] != 0.0f;
        rule = "inside the mask " + flags.mask;
        return mask;
    }
    if (!flags.threshold && !ref.foreground.empty()) {
        rule = "the reference's active voxels";
        return ref.foreground;
    }
    const auto key = [&](std::size_t n) {
        const float* v = ref.values.data() + n * ref.channels;
        return ref.channels >= 3 ? luminance(v) : double(v[0]);
    };
    double cut = 0.0;
    if (flags.threshold) {
        cut = *flags.threshold;
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
void evaluateStructures(const EvalFlags& flags, const FloatVolume& ref, const FloatVolume& test, Evaluation& e) {
    const openvdb::Int32Grid::Ptr labels = findLabelGrid(*readGridFile(flags.labels), flags.labels);
    e.labelTable = labelTableOf(*labels);
    std::string spec = flags.structures.empty() ? "all" : flags.structures;
    if (flags.structures.empty() && isAssetFile(flags.test)) {
        const GaussianAsset asset = readAsset(flags.test);
        if (!asset.labelTable.names.empty()) {
            spec.clear();
            for (const auto& [id, name] : asset.labelTable.names) spec += (spec.empty() ? "" : ",") + std::to_string(id);
        }
    }
    const std::vector<int> ids = selectLabels(e.labelTable, spec, flags.structures.empty() ? flags.labels : "--structures");
    e.structures = structureQuality(ref, test, labelsOnSamples(ref, *labels), ids, e.peak);
}

Evaluation evaluate(const EvalFlags& flags) {
    const auto start = std::chrono::steady_clock::now();
    const IngestOptions options = toIngestOptions(flags.source);
    const ComparisonInput reference = loadComparisonInput(flags.reference, options);
    ComparisonInput test = loadComparisonInput(flags.test, options);
    matchGeometry(flags, reference, test);
    Evaluation e;
    e.peak = flags.peak.value_or(reference.dataRange);
    if (!(e.peak > 0.0) || !std::isfinite(e.peak)) {
        throw InputError(flags.peak ? "--peak" : flags.reference,
                         flags.peak ? "must be a positive number" : "has no data range (a constant volume); give --peak");
    }
    const std::vector<std::uint8_t> mask = foregroundMask(flags, reference.volume, options, e.foregroundRule);
    e.foregroundVoxels = std::size_t(std::count(mask.begin(), mask.end(), 1));
    e.mse = meanSquaredError(reference.volume, test.volume);
    e.psnr = psnrFromMse(e.mse, e.peak);
    e.foregroundMse = meanSquaredError(reference.volume, test.volume, mask);
    e.foregroundPsnr = e.foregroundVoxels > 0 ? psnrFromMse(e.foregroundMse, e.peak) : NAN;
    SsimSettings ssimSettings;
    ssimSettings.dataRange = e.peak;
    e.ssim = ssim(reference.volume, test.volume, ssimSettings);
    e.msSsim = msSsim(reference.volume, test.volume, ssimSettings);
    if (!flags.labels.empty()) evaluateStructures(flags, reference.volume, test.volume, e);
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return e;
}

void printEvaluation(const EvalFlags& flags, const Evaluation& e) {
    if (flags.json) {
        nlohmann::json out = {{"reference", flags.reference}, {"test", flags.test},
                                    {"mse", e.mse}, {"psnr", jsonNumber(e.psnr)},
                                    {"fg_mse", e.foregroundMse}, {"fg_psnr", e.foregroundVoxels ? jsonNumber(e.foregroundPsnr) : nullptr},
                                    {"fg_voxels", e.foregroundVoxels}, {"fg_rule", e.foregroundRule},
                                    {"ssim", e.ssim}, {"ms_ssim", e.msSsim.value},
                                    {"ms_ssim_scales", e.msSsim.scales}, {"peak", e.peak},
                                    {"seconds", e.seconds}};
        for (const StructureQuality& q : e.structures) {
            out["structures"].push_back({{"id", q.id}, {"name", e.labelTable.nameOf(q.id)}, {"voxels", q.voxels},
                                         {"mse", q.mse}, {"psnr", jsonNumber(q.psnr)}, {"ssim", q.ssim}});
        }
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << std::setprecision(6) << "reference: " << flags.reference << "\ntest:      " << flags.test << "\n"
              << "  MSE      " << e.mse << " (physical units squared)\n"
              << "  PSNR     " << formatDb(e.psnr) << " dB, peak " << e.peak
              << (flags.peak ? " (--peak)" : " (the reference's data range)") << "\n"
              << "  FG PSNR  " << (e.foregroundVoxels ? formatDb(e.foregroundPsnr) + " dB" : std::string("n/a"))
              << " over " << e.foregroundVoxels << " voxels: " << e.foregroundRule << "\n"
              << "  SSIM     " << e.ssim << " (Gaussian window 11, sigma 1.5, K1 0.01, K2 0.03)\n"
              << "  MS-SSIM  " << e.msSsim.value << " (" << e.msSsim.scales << " scale"
              << (e.msSsim.scales == 1 ? "" : "s") << (e.msSsim.scales < 5 ? "; too small for 5" : "") << ")\n"
              << "  time     " << e.seconds << " s\n";
    if (e.structures.empty()) return;
    std::cout << "  per structure (PSNR over its voxels; SSIM of the structure cut out):\n";
    for (const StructureQuality& q : e.structures) {
        std::cout << "    " << std::setw(5) << q.id << "  " << std::left << std::setw(24) << e.labelTable.nameOf(q.id)
                  << std::right << std::setw(9) << q.voxels << " voxels  PSNR " << std::setw(6) << formatDb(q.psnr)
                  << " dB  SSIM " << std::fixed << std::setprecision(4) << q.ssim << std::defaultfloat << "\n";
    }
}

}  // namespace

void addEvalCommand(CLI::App& app) {
    auto flags = std::make_shared<EvalFlags>();
    CLI::App* command = app.add_subcommand(
        "eval", "Compare a test volume or image with a reference: MSE, PSNR, foreground PSNR, SSIM and "
                "MS-SSIM (3D for volumes, 2D for images; RGB per channel, averaged)");
    command->add_option("reference", flags->reference, "Reference: .vdb, any volume ingest reads, or a 2D image")->required();
    command->add_option("test", flags->test, "Volume, Gaussian asset (as exported) or image to compare with it")->required();
    command->add_option("--mask", flags->mask, "Foreground = the non-zero voxels of this volume");
    command->add_option("--threshold", flags->threshold,
                        "Foreground = reference voxels above this (physical units; luminance for RGB). "
                        "Default: the reference's active voxels, else those above its minimum");
    command->add_option("--peak", flags->peak, "PSNR peak (default: the reference's data range)");
    command->add_flag("--resample", flags->resample,
                      "Resample the test volume trilinearly onto the reference's grid when they differ");
    command->add_option("--labels", flags->labels,
                        "Also report PSNR and SSIM per structure, from the label grid in this .vdb (gvr ingest --labels)");
    command->add_option("--structures", flags->structures,
                        "With --labels: the structures to report, IDs or names (default: a labelled asset's own, else all)");
    addSourceFlags(*command, flags->source, /*withThreshold=*/false);
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->callback([flags] { printEvaluation(*flags, evaluate(*flags)); });
}

}  // namespace gvr
