/// @file SampleType.h
/// @brief Datatypes in which source volumes store their samples.
#pragma once

#include <cstddef>
#include <string>

namespace gvr {

enum class SampleType { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float32, Float64 };

/// Bytes one sample of this type takes in the source file.
std::size_t bytesPerSample(SampleType type);

/// Lower-case name as printed and stored in grid metadata ("uint8", "float32", ...).
std::string sampleTypeName(SampleType type);

/// Inverse of sampleTypeName. @throw InputError naming @a culprit for an unknown name.
SampleType sampleTypeFromName(const std::string& name, const std::string& culprit);

/// Calls @a visit with a value of type T (uint8_t, int16_t, float, ...) matching @a type,
/// so that code templated on the sample type is written once.
template <typename Visitor>
decltype(auto) dispatchSampleType(SampleType type, Visitor&& visit);

}  // namespace gvr

#include "pipeline/SampleTypeDispatch.h"
