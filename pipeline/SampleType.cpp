#include "pipeline/SampleType.h"

#include "pipeline/Error.h"

namespace gvr {

std::size_t bytesPerSample(SampleType type) {
    return dispatchSampleType(type, [](auto sample) { return sizeof(sample); });
}

std::string sampleTypeName(SampleType type) {
    switch (type) {
        case SampleType::UInt8:
            return "uint8";
        case SampleType::Int8:
            return "int8";
        case SampleType::UInt16:
            return "uint16";
        case SampleType::Int16:
            return "int16";
        case SampleType::UInt32:
            return "uint32";
        case SampleType::Int32:
            return "int32";
        case SampleType::Float32:
            return "float32";
        case SampleType::Float64:
            break;
    }
    return "float64";
}

SampleType sampleTypeFromName(const std::string& name, const std::string& culprit) {
    for (SampleType type : {SampleType::UInt8, SampleType::Int8, SampleType::UInt16, SampleType::Int16,
                            SampleType::UInt32, SampleType::Int32, SampleType::Float32, SampleType::Float64}) {
        if (sampleTypeName(type) == name) return type;
    }
    throw InputError(culprit, "unsupported sample type '" + name +
                                  "' (expected uint8, int8, uint16, int16, uint32, int32, "
                                  "float32 or float64)");
}

}  // namespace gvr
