// The residual codes' streams: every code (zero, small, the largest, negative,
// exact) comes back, per slab and channel, and quiet regions cost almost nothing.

#include "io/asset/ResidualCodes.h"

#include <gtest/gtest.h>

#include <random>

namespace gvr {
namespace {

ResidualLayer codedLayer(const openvdb::Coord& dims, int channels) {
    ResidualLayer layer;
    layer.dims = dims;
    layer.channels = channels;
    layer.codes.assign(std::size_t(dims.x()) * dims.y() * dims.z() * channels, 0);
    return layer;
}

std::vector<std::int32_t> roundTrip(ResidualLayer layer) {
    const std::vector<std::string> streams = encodeResidualCodes(layer);
    EXPECT_EQ(streams.size(), std::size_t(residualSlabCount(layer.dims)));
    const std::vector<std::string_view> views(streams.begin(), streams.end());
    layer.codes.assign(layer.codes.size(), 7);
    decodeResidualCodes(views, layer);
    return layer.codes;
}

TEST(ResidualCodes, EveryKindOfCodeComesBack) {
    ResidualLayer layer = codedLayer({21, 11, 70}, 3);  // three slabs, the last one short
    std::mt19937 random(11);
    std::geometric_distribution<int> small(0.3);
    std::uniform_int_distribution<int> any(-kMaxResidualCode, kMaxResidualCode);
    for (std::size_t n = 0; n < layer.codes.size(); ++n) {
        const int kind = int(n % 17);
        layer.codes[n] = kind == 0   ? kResidualExact
                         : kind == 1 ? (n % 2 ? kMaxResidualCode : -kMaxResidualCode)
                         : kind == 2 ? any(random)
                         : kind < 9  ? (n % 3 ? 1 : -1) * small(random)
                                     : 0;
    }
    EXPECT_EQ(roundTrip(layer), layer.codes);
}

TEST(ResidualCodes, AQuietVolumeCostsAFewBytesASlab) {
    ResidualLayer layer = codedLayer({64, 64, 64}, 1);
    layer.codes[1000] = -3;
    std::size_t bytes = 0;
    for (const std::string& stream : encodeResidualCodes(layer)) bytes += stream.size();
    EXPECT_LT(bytes, 200u);  // 262,144 codes
    EXPECT_EQ(roundTrip(layer), layer.codes);
}

TEST(ResidualCodes, AStreamCutShortIsRefused) {
    ResidualLayer layer = codedLayer({16, 16, 40}, 1);
    std::mt19937 random(2);
    std::uniform_int_distribution<int> any(-500, 500);
    for (auto& code : layer.codes) code = any(random);
    std::vector<std::string> streams = encodeResidualCodes(layer);
    streams[1].resize(streams[1].size() / 3);
    const std::vector<std::string_view> views(streams.begin(), streams.end());
    EXPECT_THROW(decodeResidualCodes(views, layer), std::runtime_error);
    EXPECT_THROW(decodeResidualCodes({views[0]}, layer), std::runtime_error);  // one stream for two slabs
}

}  // namespace
}  // namespace gvr
