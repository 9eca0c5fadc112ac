// dispatchSampleType(): each source datatype reaches code templated on the
// matching C++ type, so one template reads every format's samples.

#include "pipeline/SampleType.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace gvr {
namespace {

const SampleType kAll[] = {SampleType::UInt8,  SampleType::Int8,  SampleType::UInt16,  SampleType::Int16,
                           SampleType::UInt32, SampleType::Int32, SampleType::Float32, SampleType::Float64};

template <typename T>
bool dispatchesTo(SampleType type) {
    return dispatchSampleType(type, [](auto sample) { return std::is_same_v<decltype(sample), T>; });
}

TEST(SampleTypeDispatch, EachTypeReachesItsOwnCppType) {
    EXPECT_TRUE(dispatchesTo<std::uint8_t>(SampleType::UInt8));
    EXPECT_TRUE(dispatchesTo<std::int8_t>(SampleType::Int8));
    EXPECT_TRUE(dispatchesTo<std::uint16_t>(SampleType::UInt16));
    EXPECT_TRUE(dispatchesTo<std::int16_t>(SampleType::Int16));
    EXPECT_TRUE(dispatchesTo<std::uint32_t>(SampleType::UInt32));
    EXPECT_TRUE(dispatchesTo<std::int32_t>(SampleType::Int32));
    EXPECT_TRUE(dispatchesTo<float>(SampleType::Float32));
    EXPECT_TRUE(dispatchesTo<double>(SampleType::Float64));
    // Signedness matters: int16 read as uint16 turns -1 into 65535.
    EXPECT_FALSE(dispatchesTo<std::uint16_t>(SampleType::Int16));
}

TEST(SampleTypeDispatch, TheDispatchedTypeHasTheSampleSize) {
    for (SampleType type : kAll) {
        const std::size_t dispatched = dispatchSampleType(type, [](auto sample) { return sizeof(sample); });
        EXPECT_EQ(dispatched, bytesPerSample(type)) << sampleTypeName(type);
    }
}

TEST(SampleTypeDispatch, SamplesReadThroughTheDispatchKeepSignAndNaN) {
    const auto first = [](const DenseVolume& volume) {
        return dispatchSampleType(volume.type, [&](auto sample) {
            using T = decltype(sample);
            return double(volume.data<T>()[0]);
        });
    };
    EXPECT_EQ(first(test::makeVolume<std::int16_t>({1, 1, 1}, {-32768}, SampleType::Int16)), -32768.0);
    EXPECT_EQ(first(test::makeVolume<std::uint16_t>({1, 1, 1}, {65535}, SampleType::UInt16)), 65535.0);
    EXPECT_EQ(first(test::makeVolume<std::int8_t>({1, 1, 1}, {-128}, SampleType::Int8)), -128.0);
    EXPECT_TRUE(std::isnan(
        first(test::makeVolume<float>({1, 1, 1}, {std::numeric_limits<float>::quiet_NaN()}, SampleType::Float32))));
}

TEST(SampleTypeDispatch, AReferenceResultIsPassedOnNotCopied) {
    // decltype(auto): a visitor that returns a reference gives the caller that reference.
    int counter = 0;
    int& same = dispatchSampleType(SampleType::Int32, [&](auto) -> int& { return counter; });
    same = 7;
    EXPECT_EQ(counter, 7);
    EXPECT_EQ(&same, &counter);
}

}  // namespace
}  // namespace gvr
