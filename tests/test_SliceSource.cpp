// A source that decodes a slab of slices at a time, through a fake format whose
// slices are computed: slabs are the right slices with the layout's geometry,
// buffers are reused, and a volume too large to read whole is refused first.

#include "io/formats/SliceSource.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace gvr {
namespace {

/// Sample n of slice s: -32768 + 1000 s + n, so slice 0 starts at the int16 minimum.
std::int16_t sampleOf(std::int64_t slice, std::int64_t n) { return std::int16_t(-32768 + 1000 * slice + n); }

class ComputedSlices : public SliceSource {
public:
    ComputedSlices(DenseVolume layout, std::string culprit) : SliceSource(std::move(layout), std::move(culprit)) {}

    mutable std::atomic<int> decoded{0};

protected:
    void readSlices(std::int64_t first, std::int64_t count, unsigned char* destination,
                    const ProgressFn& progress) const override {
        decodeEachSlice(first, count, destination, progress, [&](std::int64_t slice, unsigned char* to) {
            const std::int64_t samples = std::int64_t(sliceBytes() / sizeof(std::int16_t));
            for (std::int64_t n = 0; n < samples; ++n) {
                const std::int16_t value = sampleOf(slice, n);
                std::memcpy(to + n * sizeof value, &value, sizeof value);
            }
            ++decoded;
        });
    }
};

DenseVolume int16Layout(std::array<std::int64_t, 3> dims) {
    DenseVolume layout;
    layout.dims = dims;
    layout.type = SampleType::Int16;
    layout.slope = 2.0;
    layout.intercept = -1.0;
    layout.worldFromIndex = worldFromSpacing(openvdb::Vec3d(0.5, 0.5, 3.0));
    layout.modality = "CT";
    layout.warnings = {"voxel spacing is assumed"};
    return layout;
}

void expectSlices(const DenseVolume& slab, std::int64_t first) {
    const std::int64_t perSlice = slab.dims[0] * slab.dims[1];
    ASSERT_EQ(slab.samples.size(), std::size_t(perSlice * slab.dims[2]) * 2);
    for (std::int64_t s = 0; s < slab.dims[2]; ++s) {
        for (std::int64_t n = 0; n < perSlice; ++n) {
            ASSERT_EQ(slab.data<std::int16_t>()[s * perSlice + n], sampleOf(first + s, n)) << s << " " << n;
        }
    }
}

TEST(SliceSource, SliceBytesCountWidthHeightChannelsAndSampleSize) {
    DenseVolume layout = int16Layout({3, 2, 4});
    EXPECT_EQ(ComputedSlices(layout, "v").sliceBytes(), 12u);
    layout.channels = 3;
    layout.type = SampleType::Float64;
    EXPECT_EQ(ComputedSlices(layout, "v").sliceBytes(), 3u * 2u * 3u * 8u);
    // The largest slice OpenVDB's coordinates allow does not wrap 32 bits.
    layout.dims = {std::int64_t(1) << 30, std::int64_t(1) << 30, 1};
    layout.channels = 1;
    layout.type = SampleType::UInt8;
    EXPECT_EQ(ComputedSlices(layout, "v").sliceBytes(), std::uint64_t(1) << 60);
}

TEST(SliceSource, ASlabIsItsSlicesWithTheLayoutsGeometryAndNoWarnings) {
    const ComputedSlices source(int16Layout({3, 2, 5}), "series/");
    DenseVolume slab;
    slab.warnings = {"left over"};
    source.readSlab(2, 3, slab);
    EXPECT_EQ(slab.dims, (std::array<std::int64_t, 3>{3, 2, 3}));
    EXPECT_EQ(slab.type, SampleType::Int16);
    EXPECT_EQ(slab.slope, 2.0);
    EXPECT_EQ(slab.intercept, -1.0);
    EXPECT_EQ(slab.modality, "CT");
    EXPECT_EQ(slab.worldFromIndex, source.layout().worldFromIndex);
    EXPECT_TRUE(slab.warnings.empty());  // the whole volume's warnings are said once, not per slab
    expectSlices(slab, 2);
    EXPECT_EQ(source.decoded.load(), 3);
    EXPECT_TRUE(source.layout().samples.empty());
    EXPECT_EQ(source.layout().dims[2], 5);
}

TEST(SliceSource, ALaterSlabOfTheSameSizeReusesTheBuffer) {
    const ComputedSlices source(int16Layout({3, 2, 6}), "v.raw");
    DenseVolume slab;
    source.readSlab(0, 2, slab);
    const unsigned char* buffer = slab.samples.data();
    source.readSlab(4, 2, slab);
    EXPECT_EQ(slab.samples.data(), buffer);
    expectSlices(slab, 4);
    source.readSlab(5, 1, slab);  // the volume's last, shorter slab
    expectSlices(slab, 5);
}

TEST(SliceSource, SlicesOutsideTheVolumeAreALogicErrorNotARead) {
    const ComputedSlices source(int16Layout({3, 2, 4}), "v.raw");
    DenseVolume slab;
    EXPECT_THROW(source.readSlab(-1, 2, slab), std::out_of_range);
    EXPECT_THROW(source.readSlab(0, 0, slab), std::out_of_range);
    EXPECT_THROW(source.readSlab(3, 2, slab), std::out_of_range);
    EXPECT_THROW(source.readSlab(0, 5, slab), std::out_of_range);
    EXPECT_EQ(source.decoded.load(), 0);
    source.readSlab(3, 1, slab);
    expectSlices(slab, 3);
}

TEST(SliceSource, TheWholeVolumeKeepsTheWarningsAndReportsEverySlice) {
    const ComputedSlices source(int16Layout({4, 3, 5}), "v.raw");
    std::vector<double> fractions;
    const DenseVolume volume = readWholeVolume(source, [&](double f) { fractions.push_back(f); });
    EXPECT_EQ(volume.dims, (std::array<std::int64_t, 3>{4, 3, 5}));
    expectSlices(volume, 0);
    EXPECT_EQ(volume.data<std::int16_t>()[0], -32768);
    EXPECT_EQ(volume.warnings, std::vector<std::string>{"voxel spacing is assumed"});
    ASSERT_EQ(fractions.size(), 5u);
    EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
}

TEST(SliceSource, AVolumeTooLargeToReadWholeIsRefusedBeforeAnyDecoding) {
    const std::int64_t huge = std::int64_t(1) << 30;
    const ComputedSlices source(int16Layout({huge, huge, huge}), "huge.raw");
    const std::string message = test::errorMessageOf<InputError>([&] { readWholeVolume(source); });
    EXPECT_EQ(message.rfind("huge.raw: a volume of 1073741824x1073741824x1073741824 voxels needs ", 0), 0u) << message;
    EXPECT_NE(message.find("to read whole"), std::string::npos) << message;
    EXPECT_EQ(source.decoded.load(), 0);
}

}  // namespace
}  // namespace gvr
