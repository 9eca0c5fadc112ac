#include "io/formats/SliceSource.h"

#include "io/guard/MemoryBudget.h"

#include <tbb/parallel_for.h>

#include <stdexcept>

namespace gvr {

std::uint64_t SliceSource::sliceBytes() const {
    return std::uint64_t(mLayout.dims[0]) * std::uint64_t(mLayout.dims[1]) * std::uint64_t(mLayout.channels) *
           bytesPerSample(mLayout.type);
}

void SliceSource::readSlab(std::int64_t first, std::int64_t count, DenseVolume& slab,
                           const ProgressFn& progress) const {
    if (first < 0 || count < 1 || first + count > mLayout.dims[2]) {
        throw std::out_of_range("SliceSource::readSlab: slices outside the volume");
    }
    std::vector<unsigned char> buffer = std::move(slab.samples);
    slab = mLayout;
    slab.warnings.clear();
    slab.dims[2] = count;
    buffer.resize(slab.sampleBytes());  // a later slab of the same size reuses the memory
    slab.samples = std::move(buffer);
    readSlices(first, count, slab.samples.data(), progress);
}

void SliceSource::decodeEachSlice(std::int64_t first, std::int64_t count, unsigned char* destination,
                                  const ProgressFn& progress,
                                  const std::function<void(std::int64_t, unsigned char*)>& decodeSlice) const {
    ProgressCounter counter(progress, std::size_t(count));
    const std::uint64_t bytes = sliceBytes();
    tbb::parallel_for(std::int64_t(0), count, [&](std::int64_t s) {
        decodeSlice(first + s, destination + std::uint64_t(s) * bytes);
        counter.advance();
    });
}

DenseVolume readWholeVolume(const SliceSource& source, const ProgressFn& progress) {
    const DenseVolume& layout = source.layout();
    checkVolumeFitsInMemory(source.culprit(), layout.dims, layout.channels, bytesPerSample(layout.type), "read whole");
    DenseVolume volume;
    source.readSlab(0, layout.dims[2], volume, progress);
    volume.warnings = layout.warnings;
    return volume;
}

}  // namespace gvr
