/// @file Evaluate.h
/// @brief A test volume against a reference: MSE, PSNR, foreground PSNR, SSIM,
/// MS-SSIM, and per structure, as `gvr eval` reports them.
#pragma once

#include "pipeline/LabelTable.h"
#include "pipeline/QualityMetrics.h"
#include "pipeline/StructureQuality.h"
#include "workflow/ComparisonInput.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace gvr {

struct EvalOptions {
    std::string mask;                 ///< foreground = the non-zero voxels of this volume
    std::optional<double> threshold;  ///< foreground = reference above this (physical; luminance for RGB)
    std::optional<double> peak;       ///< PSNR peak; default: the reference's data range
    bool resample = false;            ///< resample the test onto the reference when they differ
    /// Also report per structure, from the label grid that ingest --labels stored in
    /// this .vdb, or from a label volume ingest reads (an atlas such as aal.nii.gz).
    std::string labels;
    std::string labelNames;  ///< with a label volume: "ID NAME" lines (as ingest --label-names)
    /// With @a labels, the structures to report (ids or names); default: those of a
    /// labelled test asset, else all.
    std::string structures;
    IngestOptions ingest;  ///< how inputs that are not .vdb files are read
    /// For two RGBA renderings: write where they differ (renderingDifference) to this
    /// image, its errors times differenceGain.
    std::string differenceImage;
    float differenceGain = 4.0f;
};

/// Two RGBA renderings as they are seen (see renderingError): PSNR with a peak of
/// 1 over black, over white, and of the mean of the two errors, which is what
/// `gvr bench` reports as render PSNR.
struct RenderingQuality {
    double psnr = 0, psnrOverBlack = 0, psnrOverWhite = 0;
    std::size_t coveredPixels = 0;
};

/// @throw std::invalid_argument unless both have 4 channels and the same shape.
RenderingQuality renderingQuality(const FloatVolume& reference, const FloatVolume& test);

struct EvalResult {
    double mse = 0, psnr = 0, foregroundMse = 0, foregroundPsnr = 0, ssim = 0, peak = 0, seconds = 0;
    double maxError = 0;  ///< the largest |reference - test| over the voxels compared, as an error bound reads it
    std::optional<RenderingQuality> rendering;  ///< for two RGBA images
    std::size_t foregroundVoxels = 0;
    MsSsim msSsim;
    std::string foregroundRule;   ///< how the foreground was chosen, in words
    std::string referenceReadAs;  ///< how the reference was read (ComparisonInput::readAs)
    /// Reference voxels left out of MSE and PSNR, and given the same value in both
    /// volumes for SSIM: those its format marks as no data.
    std::size_t excludedVoxels = 0;
    std::vector<StructureQuality> structures;
    LabelTable labelTable;
};

/// Compares two volumes or two images in memory. @a referenceName and @a testName
/// name them in errors. Without options.structures, every structure of
/// options.labels is reported.
/// @throw InputError naming the input at fault: other channels, another grid
///        without options.resample, a constant reference without a peak.
EvalResult evaluate(const ComparisonInput& reference, ComparisonInput test, const EvalOptions& options,
                    const std::string& referenceName, const std::string& testName);

/// Compares the files @a reference and @a test: .vdb grids, Gaussian assets, anything
/// ingest reads, or two 2D images. Without options.structures, a labelled test
/// asset's own structures are reported.
/// @throw InputError as above, or naming a file that cannot be read.
EvalResult evaluate(const std::string& reference, const std::string& test, const EvalOptions& options);

/// The result with the keys of `gvr eval --json` (an infinite PSNR as "inf").
nlohmann::json evalResultJson(const EvalResult& result);

}  // namespace gvr
