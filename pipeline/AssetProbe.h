/// @file AssetProbe.h
/// @brief What an asset's field holds at points of its source's index space, in
/// the source's physical units.
#pragma once

#include "pipeline/GaussianAsset.h"
#include "pipeline/GaussianField.h"

#include <array>
#include <cstddef>
#include <vector>

namespace gvr {

class AssetProbe {
public:
    explicit AssetProbe(const GaussianAsset& asset);

    struct Sample {
        std::array<double, 3> value{};  ///< physical units; channels() of them
        std::size_t gaussians = 0;      ///< Gaussians that reach the point
    };
    /// The field at index-space point @a index (fractional indices interpolate nothing:
    /// the field is continuous). Not thread-safe: one probe per thread.
    Sample at(const std::array<double, 3>& index);

    int channels() const { return mField.channels(); }

private:
    GaussianField mField;
    ValueMapping mMapping;
    std::vector<std::uint32_t> mHits;
};

}  // namespace gvr
