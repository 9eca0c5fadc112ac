// Source datatypes: their sizes, their names both ways, and the dispatch to the
// matching C++ type.

#include "pipeline/Error.h"
#include "pipeline/SampleType.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>

namespace gvr {
namespace {

const SampleType kAll[] = {SampleType::UInt8,  SampleType::Int8,  SampleType::UInt16,  SampleType::Int16,
                           SampleType::UInt32, SampleType::Int32, SampleType::Float32, SampleType::Float64};

TEST(SampleType, NamesRoundTripAndSizesMatchTheDispatchedType) {
    for (SampleType type : kAll) {
        EXPECT_EQ(sampleTypeFromName(sampleTypeName(type), "test"), type) << sampleTypeName(type);
        const std::size_t dispatched = dispatchSampleType(type, [](auto sample) { return sizeof(sample); });
        EXPECT_EQ(dispatched, bytesPerSample(type)) << sampleTypeName(type);
    }
    EXPECT_EQ(sampleTypeName(SampleType::Int16), "int16");
    EXPECT_TRUE((dispatchSampleType(SampleType::Int16, [](auto sample) { return std::is_same_v<decltype(sample), std::int16_t>; })));
}

TEST(SampleType, AnUnknownNameIsRefusedNamingTheCulprit) {
    try {
        sampleTypeFromName("complex64", "--raw-type");
        FAIL() << "complex64 was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("--raw-type"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("complex64"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace gvr
