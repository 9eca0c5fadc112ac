// gvr eval REFERENCE TEST: MSE, PSNR, foreground PSNR, SSIM and MS-SSIM.

#include "cli/Commands.h"
#include "cli/SourceOptions.h"
#include "io/formats/JsonText.h"
#include "io/guard/AtomicFile.h"
#include "workflow/Evaluate.h"
#include "workflow/ReportNumbers.h"

#include <iomanip>
#include <iostream>

namespace gvr {

namespace {

struct EvalFlags {
    std::string reference, test;
    bool json = false;
    EvalOptions options;
    SourceFlags source;
};

void printEvaluation(const EvalFlags& flags, const EvalResult& e) {
    if (flags.json) {
        nlohmann::json out = evalResultJson(e);
        out["reference"] = flags.reference;
        out["test"] = flags.test;
        std::cout << jsonText(out, 2) << "\n";
        return;
    }
    std::cout << std::setprecision(6) << "reference: " << flags.reference
              << (e.referenceReadAs.empty() ? "" : " (" + e.referenceReadAs + ")") << "\ntest:      " << flags.test
              << "\n"
              << "  MSE      " << e.mse << " (physical units squared)\n"
              << "  max err  " << e.maxError << " (physical units, the largest over the voxels compared)\n"
              << "  PSNR     " << formatDb(e.psnr) << " dB, peak " << e.peak
              << (flags.options.peak ? " (--peak)" : " (the reference's data range)") << "\n"
              << "  FG PSNR  " << (e.foregroundVoxels ? formatDb(e.foregroundPsnr) + " dB" : std::string("n/a"))
              << " over " << e.foregroundVoxels << " voxels: " << e.foregroundRule << "\n"
              << "  SSIM     " << e.ssim << " (Gaussian window 11, sigma 1.5, K1 0.01, K2 0.03)\n"
              << "  MS-SSIM  " << e.msSsim.value << " (" << e.msSsim.scales << " scale"
              << (e.msSsim.scales == 1 ? "" : "s") << (e.msSsim.scales < 5 ? "; too small for 5" : "") << ")\n"
              << "  time     " << e.seconds << " s\n";
    if (e.rendering) {
        std::cout << "  as seen  " << formatDb(e.rendering->psnr) << " dB: premultiplied RGB over black ("
                  << formatDb(e.rendering->psnrOverBlack) << " dB) and over white ("
                  << formatDb(e.rendering->psnrOverWhite) << " dB), MSE averaged, on the " << e.rendering->coveredPixels
                  << " pixels either image covers, peak 1\n";
    }
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
        "eval",
        "Compare a test volume or image with a reference: MSE, maximum error, PSNR, foreground PSNR, SSIM and "
        "MS-SSIM (3D for volumes, 2D for images; RGB per channel, averaged)");
    command->add_option("reference", flags->reference, "Reference: .vdb, any volume ingest reads, or a 2D image")
        ->required();
    command->add_option("test", flags->test, "Volume, Gaussian asset (as exported) or image to compare with it")
        ->required();
    command->add_option("--mask", flags->options.mask, "Foreground = the non-zero voxels of this volume");
    command->add_option("--threshold", flags->options.threshold,
                        "Foreground = reference voxels above this (physical units; luminance for RGB). "
                        "Default: the reference's active voxels, else those above its minimum");
    command->add_option("--peak", flags->options.peak, "PSNR peak (default: the reference's data range)");
    command->add_flag("--resample", flags->options.resample,
                      "Resample the test volume trilinearly onto the reference's grid when they differ");
    command->add_option(
        "--labels", flags->options.labels,
        "Also report PSNR and SSIM per structure: the label grid in a .vdb from gvr ingest --labels, "
        "or a label volume such as an atlas (any format ingest reads; nearest neighbour onto the reference)");
    command->add_option("--label-names", flags->options.labelNames,
                        "With a label volume: structure names, one 'ID NAME' per line (AAL .txt, FreeSurfer LUT)");
    command->add_option(
        "--structures", flags->options.structures,
        "With --labels: the structures to report, IDs or names (default: a labelled asset's own, else all)");
    addSourceFlags(*command, flags->source, /*withThreshold=*/false);
    command->add_option("--difference", flags->options.differenceImage,
                        "For two renderings (RGBA images): write where they differ to this .png or .exr, each pixel's "
                        "error as seen (over black and white, as the PSNR \"as seen\") times --difference-gain");
    command->add_option("--difference-gain", flags->options.differenceGain, "Scale of the --difference image")
        ->capture_default_str();
    command->add_flag("--json", flags->json, "Print the result as JSON");
    command->callback([flags] {
        const EvalOptions& options = flags->options;
        if (!options.differenceImage.empty()) {
            checkOutputPath("--difference", options.differenceImage,
                            {flags->reference, flags->test, options.mask, options.labels});
        }
        flags->options.ingest = toIngestOptions(flags->source);
        printEvaluation(*flags, evaluate(flags->reference, flags->test, flags->options));
    });
}

}  // namespace gvr
