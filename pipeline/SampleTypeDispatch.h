/// @file SampleTypeDispatch.h
/// @brief Implementation of dispatchSampleType(); include SampleType.h instead.
#pragma once

#include <cstdint>

namespace gvr {

template <typename Visitor>
decltype(auto) dispatchSampleType(SampleType type, Visitor&& visit) {
    switch (type) {
        case SampleType::UInt8:
            return visit(std::uint8_t{});
        case SampleType::Int8:
            return visit(std::int8_t{});
        case SampleType::UInt16:
            return visit(std::uint16_t{});
        case SampleType::Int16:
            return visit(std::int16_t{});
        case SampleType::UInt32:
            return visit(std::uint32_t{});
        case SampleType::Int32:
            return visit(std::int32_t{});
        case SampleType::Float32:
            return visit(float{});
        case SampleType::Float64:
            break;
    }
    return visit(double{});
}

}  // namespace gvr
