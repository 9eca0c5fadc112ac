// The range coder: bits come back as they went in, skewed bits cost far less than
// a bit each, and a cut stream decodes without reading out of bounds.

#include "io/asset/RangeCoder.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace gvr {
namespace {

std::vector<bool> randomBits(std::size_t count, double oneProbability, unsigned seed) {
    std::mt19937 random(seed);
    std::bernoulli_distribution one(oneProbability);
    std::vector<bool> bits(count);
    for (std::size_t n = 0; n < count; ++n) bits[n] = one(random);
    return bits;
}

std::string encodeBits(const std::vector<bool>& bits) {
    RangeEncoder coder;
    BitModel model;
    for (const bool bit : bits) coder.encode(model, bit);
    return coder.finish();
}

TEST(RangeCoder, BitsComeBackAsTheyWentIn) {
    for (const double p : {0.5, 0.1, 0.001, 0.999}) {
        const std::vector<bool> bits = randomBits(20000, p, 3);
        const std::string bytes = encodeBits(bits);
        RangeDecoder decoder(bytes);
        BitModel model;
        for (std::size_t n = 0; n < bits.size(); ++n) ASSERT_EQ(decoder.decode(model), bits[n]) << p << " at " << n;
        EXPECT_FALSE(decoder.overran());
    }
}

TEST(RangeCoder, SkewedBitsCostAboutTheirEntropy) {
    // p = 0.01: 0.081 bits a bit. An order-0 model that learns costs a little more.
    const std::size_t count = 100000;
    const std::string bytes = encodeBits(randomBits(count, 0.01, 5));
    EXPECT_LT(8.0 * double(bytes.size()) / double(count), 0.095);
    EXPECT_GT(8.0 * double(bytes.size()) / double(count), 0.070);
    // Constant bits: a few bytes for the whole run.
    EXPECT_LT(encodeBits(std::vector<bool>(count, false)).size(), 40u);
}

TEST(RangeCoder, ACutStreamDecodesWithinBoundsAndSaysSo) {
    const std::vector<bool> bits = randomBits(5000, 0.5, 9);
    const std::string bytes = encodeBits(bits);
    RangeDecoder decoder(std::string_view(bytes).substr(0, bytes.size() / 2));
    BitModel model;
    for (std::size_t n = 0; n < bits.size(); ++n) decoder.decode(model);
    EXPECT_TRUE(decoder.overran());
}

}  // namespace
}  // namespace gvr
