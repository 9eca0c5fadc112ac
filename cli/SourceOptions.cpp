#include "cli/SourceOptions.h"

#include "pipeline/Error.h"

#include <cmath>
#include <sstream>

namespace gvr {

void addSourceFlags(CLI::App& command, SourceFlags& flags, bool withThreshold) {
    command.add_option("--volume", flags.volume, "Volume of a 4D NIfTI or frame of an MGH to read")
        ->check(CLI::Range(0, 1 << 30));
    command.add_option("--spacing", flags.spacing, "Voxel size X,Y,Z in mm for stacks and raw data (default 1,1,1)")
        ->delimiter(',')
        ->expected(3);
    command.add_option("--raw-dims", flags.rawDims, "Read INPUT as raw samples of X,Y,Z voxels")
        ->delimiter(',')
        ->expected(3);
    command.add_option("--raw-type", flags.rawType,
                       "Raw sample type: uint8, int8, uint16, int16, uint32, int32, float32, float64");
    command.add_option("--endian", flags.endian, "Raw byte order")->check(CLI::IsMember({"little", "big"}));
    command.add_option("--header-bytes", flags.headerBytes, "Bytes to skip before raw samples");
    command.add_option("--raw-channels", flags.rawChannels, "Raw channels per voxel: 1 grey, 3 RGB")
        ->check(CLI::IsMember({1, 3}));
    if (withThreshold) {
        command.add_option("--threshold", flags.threshold,
                           "Deactivate voxels at or below this value (physical units, e.g. HU; "
                           "luminance for RGB). Default: -950 for a CT (air out, lungs kept), else only the "
                           "volume's minimum (for RGB, only when it holds 1 % of the voxels: a section on paper "
                           "keeps its darkest voxels, and the paper is what lies outside)");
        command.add_option("--threshold-above", flags.thresholdAbove,
                           "Deactivate voxels at or above this value too: a bright background such as the white "
                           "paper behind a cryosection (luminance for RGB)");
    }
    command.add_option("--flip", flags.flip,
                       "Mirror index axes, comma-separated: i (columns), j (rows), k (slices); e.g. j,k turns a "
                       "stack read head-down upright. The world follows the data");
    command.add_option("--nan-to", flags.nanTo,
                       "Replace NaN/Inf samples with this value "
                       "(default: reject the file)");
    command.add_option("--modality", flags.modality, "Override the modality (CT, MR, ...)");
    command.add_flag("--data-files-anywhere", flags.dataFilesAnywhere,
                     "Let a header (MetaImage ElementDataFile) name a data file outside its own folder");
}

namespace {

/// "j,k" as flags for i, j and k. @throw InputError naming --flip for anything else.
std::array<bool, 3> flippedAxes(const std::string& text) {
    std::array<bool, 3> flip{false, false, false};
    // getline() yields no empty token after a trailing comma, so "j," would pass unseen.
    if (!text.empty() && text.back() == ',') {
        throw InputError("--flip", "'" + text + "' ends with a comma: give i, j and/or k, comma-separated");
    }
    std::istringstream in(text);
    for (std::string axis; std::getline(in, axis, ',');) {
        if (axis != "i" && axis != "j" && axis != "k") {
            throw InputError("--flip", "'" + axis + "' is no index axis: give i, j and/or k, comma-separated");
        }
        flip[axis[0] - 'i'] = true;
    }
    return flip;
}

}  // namespace

IngestOptions toIngestOptions(const SourceFlags& flags) {
    IngestOptions options;
    options.read.volumeIndex = flags.volume;
    options.read.dataFilesAnywhere = flags.dataFilesAnywhere;
    if (!flags.spacing.empty()) {
        for (double s : flags.spacing) {
            if (!(s > 0.0) || !std::isfinite(s)) {
                throw InputError("--spacing", "each voxel size must be a positive number of mm");
            }
        }
        options.read.spacingMm = openvdb::Vec3d(flags.spacing[0], flags.spacing[1], flags.spacing[2]);
    }
    if (!flags.rawDims.empty()) {
        if (flags.rawType.empty()) throw InputError("--raw-dims", "needs --raw-type as well");
        RawLayout raw;
        raw.dims = {flags.rawDims[0], flags.rawDims[1], flags.rawDims[2]};
        raw.type = sampleTypeFromName(flags.rawType, "--raw-type");
        raw.channels = flags.rawChannels;
        raw.bigEndian = flags.endian == "big";
        raw.headerBytes = flags.headerBytes;
        options.read.raw = raw;
    } else if (!flags.rawType.empty()) {
        throw InputError("--raw-type", "needs --raw-dims as well");
    }
    options.build.threshold = flags.threshold;
    options.build.thresholdAbove = flags.thresholdAbove;
    options.build.flip = flippedAxes(flags.flip);
    options.build.nanTo = flags.nanTo;
    options.build.modality = flags.modality;
    options.build.validate();
    return options;
}

}  // namespace gvr
