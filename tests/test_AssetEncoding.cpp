// The bit depths an asset keeps: the measured defaults, the ranges the comments
// promise (which the encoder enforces), and their trip through an asset's header.

#include "io/asset/AssetBodyV2.h"
#include "pipeline/AssetEncoding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace gvr {
namespace {

TEST(AssetEncoding, DefaultsAreTheMeasuredDepths) {
    const AssetEncoding e;
    EXPECT_EQ(e.meanStep, 0.125f);
    EXPECT_EQ(e.rotationBits, 7);
    EXPECT_EQ(e.logScaleBits, 7);
    EXPECT_EQ(e.amplitudeBits, 10);
    EXPECT_EQ(e.zstdLevel, 19);
}

TEST(AssetEncoding, TheDocumentedRangesAreWhatTheEncoderAccepts) {
    const GaussianParameters params(1, 1);
    const auto accepted = [&](const AssetEncoding& e) {
        try {
            QuantisationV2 quantisation(params, e);
            return true;
        } catch (const std::runtime_error&) {
            return false;
        }
    };
    EXPECT_TRUE(accepted(AssetEncoding{}));
    AssetEncoding e;
    e.rotationBits = 2;
    EXPECT_TRUE(accepted(e));
    e.rotationBits = 15;
    EXPECT_TRUE(accepted(e));
    e.rotationBits = 16;  // "2-15": the packed rotation has no room for more
    EXPECT_FALSE(accepted(e));
    e = AssetEncoding{};
    e.logScaleBits = 16;
    EXPECT_TRUE(accepted(e));
    e.logScaleBits = 1;
    EXPECT_FALSE(accepted(e));
    e = AssetEncoding{};
    e.amplitudeBits = 16;
    EXPECT_TRUE(accepted(e));
    e.amplitudeBits = 17;
    EXPECT_FALSE(accepted(e));
    e = AssetEncoding{};
    for (const float step : {0.0f, -0.125f, NAN, INFINITY}) {
        e.meanStep = step;
        EXPECT_FALSE(accepted(e)) << step;
    }
}

TEST(AssetEncoding, AChosenEncodingSurvivesTheHeader) {
    GaussianParameters params(2, 1);
    params.at(kMeans, 1)[0] = 5.0f;
    AssetEncoding chosen;
    chosen.meanStep = 0.25f;
    chosen.rotationBits = 9;
    chosen.logScaleBits = 5;
    chosen.amplitudeBits = 12;
    const QuantisationV2 written(params, chosen);
    const QuantisationV2 read(written.json(), 1);
    EXPECT_EQ(read.encoding.meanStep, 0.25f);
    EXPECT_EQ(read.encoding.rotationBits, 9);
    EXPECT_EQ(read.encoding.logScaleBits, 5);
    EXPECT_EQ(read.encoding.amplitudeBits, 12);
}

}  // namespace
}  // namespace gvr
