#include "SourceOptions.h"

#include "Error.h"

#include <cmath>

namespace gvr {

void addSourceFlags(CLI::App& command, SourceFlags& flags, bool withThreshold) {
    command.add_option("--volume", flags.volume, "Volume of a 4D NIfTI or frame of an MGH to read")
        ->check(CLI::Range(0, 1 << 30));
    command.add_option("--spacing", flags.spacing,
                       "Voxel size X,Y,Z in mm for stacks and raw data (default 1,1,1)")
        ->delimiter(',')->expected(3);
    command.add_option("--raw-dims", flags.rawDims, "Read INPUT as raw samples of X,Y,Z voxels")
        ->delimiter(',')->expected(3);
    command.add_option("--raw-type", flags.rawType,
                       "Raw sample type: uint8, int8, uint16, int16, uint32, int32, float32, float64");
    command.add_option("--endian", flags.endian, "Raw byte order")
        ->check(CLI::IsMember({"little", "big"}));
    command.add_option("--header-bytes", flags.headerBytes, "Bytes to skip before raw samples");
    command.add_option("--raw-channels", flags.rawChannels, "Raw channels per voxel: 1 grey, 3 RGB")
        ->check(CLI::IsMember({1, 3}));
    if (withThreshold) {
        command.add_option("--threshold", flags.threshold,
                           "Deactivate voxels at or below this value (physical units, e.g. HU; "
                           "luminance for RGB). Default: only the volume's minimum");
    }
    command.add_option("--nan-to", flags.nanTo, "Replace NaN/Inf samples with this value "
                                                "(default: reject the file)");
    command.add_option("--modality", flags.modality, "Override the modality (CT, MR, ...)");
    command.add_flag("--data-files-anywhere", flags.dataFilesAnywhere,
                     "Let a header (MetaImage ElementDataFile) name a data file outside its own folder");
}

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
    if (flags.threshold && !std::isfinite(*flags.threshold)) {
        throw InputError("--threshold", "must be a finite number");
    }
    options.build.threshold = flags.threshold;
    options.build.nanTo = flags.nanTo;
    if (flags.nanTo && !std::isfinite(*flags.nanTo)) {
        throw InputError("--nan-to", "must be a finite number");
    }
    options.build.modality = flags.modality;
    return options;
}

}  // namespace gvr
