#include "io/DenseVolume.h"

#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"

namespace gvr {

openvdb::math::Mat4d worldFromIndexRows(const double rows[3][4]) {
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) m(c, r) = rows[r][c];  // OpenVDB transposes
    }
    return m;
}

openvdb::math::Mat4d worldFromSpacing(const openvdb::Vec3d& spacingMm) {
    const double rows[3][4] = {{spacingMm[0], 0, 0, 0}, {0, spacingMm[1], 0, 0}, {0, 0, spacingMm[2], 0}};
    return worldFromIndexRows(rows);
}

void allocateSamples(DenseVolume& volume, const std::string& file) {
    checkVolumeFitsInMemory(file, volume.dims, volume.channels, bytesPerSample(volume.type));
    volume.samples.assign(volume.sampleBytes(), 0);
}

void reserveSamples(DenseVolume& volume, const std::string& file) {
    checkVolumeFitsInMemory(file, volume.dims, volume.channels, bytesPerSample(volume.type));
    volume.samples.clear();
    volume.samples.reserve(volume.sampleBytes());
}

}  // namespace gvr
