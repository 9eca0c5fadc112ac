#include "cli/VolumeOutputOptions.h"

#include "cli/Diagnostics.h"
#include "cli/GridSummary.h"
#include "pipeline/Error.h"

#include <iostream>
#include <sstream>

namespace gvr {

namespace {

std::string formatName(VolumeFileFormat format) { return format == VolumeFileFormat::Vdb ? "vdb" : "nifti"; }

/// "uint8, scl_slope 7.1098, scl_inter -1024, sform code 2": what a NIfTI reader will find.
std::string describeStorage(const NiftiStorage& storage) {
    std::ostringstream text;
    text << sampleTypeName(storage.type);
    if (storage.slope != 1.0 || storage.intercept != 0.0) {
        text << ", scl_slope " << storage.slope << ", scl_inter " << storage.intercept;
    }
    text << ", sform code " << storage.codes.sform << ", qform code " << storage.codes.qform;
    return text.str();
}

}  // namespace

void addVolumeOutputOptions(CLI::App& command, std::vector<std::string>& outputs, bool& float32) {
    command
        .add_option("-o,--output", outputs,
                    "Output file; its extension chooses the format: .vdb (OpenVDB grids), .nii or .nii.gz "
                    "(NIfTI in the source's datatype and codes). Repeat -o for both")
        ->required();
    command.add_flag("--float32", float32, "NIfTI: store float32 samples instead of the source's datatype");
}

void addRemovedFormatOption(CLI::App& command, std::string& format) {
    command.add_option("--format", format)->group("");
}

void rejectRemovedFormat(const std::string& format) {
    if (format.empty()) return;
    throw InputError("--format",
                     "was removed: the extension of -o chooses the format; for a VDB and a NIfTI "
                     "pass -o OUT.vdb -o OUT.nii.gz");
}

nlohmann::json toJson(const std::vector<WrittenVolume>& written, const NiftiStorage& storage) {
    nlohmann::json files = nlohmann::json::array();
    for (const WrittenVolume& file : written) {
        nlohmann::json entry = {
            {"path", file.path}, {"format", formatName(file.format)}, {"file_bytes", file.fileBytes}};
        if (file.format == VolumeFileFormat::Nifti) {
            entry["datatype"] = sampleTypeName(storage.type);
            entry["scl_slope"] = storage.slope;
            entry["scl_inter"] = storage.intercept;
            entry["sform_code"] = storage.codes.sform;
            entry["qform_code"] = storage.codes.qform;
            entry["clamped_samples"] = file.clampedSamples;
            if (!storage.float32Reason.empty()) entry["float32_because"] = storage.float32Reason;
        }
        files.push_back(entry);
    }
    return files;
}

void printWritten(const std::vector<WrittenVolume>& written, const NiftiStorage& storage) {
    for (const WrittenVolume& file : written) {
        std::cout << "wrote " << file.path << " (" << formatBytes(file.fileBytes) << ")";
        if (file.format == VolumeFileFormat::Nifti) {
            std::cout << ": NIfTI, " << describeStorage(storage);
            if (!storage.float32Reason.empty()) {
                diagnostics() << "gvr: warning: " << file.path << " is float32: " << storage.float32Reason << "\n";
            }
            if (file.clampedSamples > 0) {
                diagnostics() << "gvr: warning: " << file.path << ": " << file.clampedSamples
                              << " samples were clamped into " << sampleTypeName(storage.type)
                              << "'s range (pass --float32 to keep them)\n";
            }
        }
        std::cout << "\n";
    }
}

}  // namespace gvr
