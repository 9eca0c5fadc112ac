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
    setGivenSpacing(options, volume);
    reserveSamples(volume, path);  // the sample reader allocates as data arrives
    readPlainSamples(path, layout.headerBytes, layout.bigEndian, volume);
    return volume;
}

}  // namespace gvr
