// Headerless raw samples, laid out as the user says (--raw-dims, --raw-type, ...).

#include "Readers.h"
#include "SampleFile.h"

namespace gvr {

DenseVolume readRaw(const std::string& path, const ReadOptions& options) {
    const RawLayout& layout = *options.raw;
    DenseVolume volume;
    volume.dims = layout.dims;
    volume.type = layout.type;
    volume.channels = layout.channels;
    const openvdb::Vec3d spacing = spacingOrDefault(options, volume);
    const double rows[3][4] = {{spacing[0], 0, 0, 0}, {0, spacing[1], 0, 0}, {0, 0, spacing[2], 0}};
    volume.worldFromIndex = worldFromIndexRows(rows);
    allocateSamples(volume, path);
    readPlainSamples(path, layout.headerBytes, layout.bigEndian, volume);
    return volume;
}

}  // namespace gvr
