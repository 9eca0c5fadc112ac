// Source datatypes: their names both ways (the dispatch to C++ types is in
// test_SampleTypeDispatch.cpp).

#include "pipeline/Error.h"
#include "pipeline/SampleType.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

const SampleType kAll[] = {SampleType::UInt8,  SampleType::Int8,  SampleType::UInt16,  SampleType::Int16,
                           SampleType::UInt32, SampleType::Int32, SampleType::Float32, SampleType::Float64};

TEST(SampleType, NamesRoundTrip) {
    for (SampleType type : kAll) {
        EXPECT_EQ(sampleTypeFromName(sampleTypeName(type), "test"), type) << sampleTypeName(type);
    }
    EXPECT_EQ(sampleTypeName(SampleType::Int16), "int16");
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
