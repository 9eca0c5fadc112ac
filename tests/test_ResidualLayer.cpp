// The residual layer: every voxel within the bound after decoding, on volumes made
// to break it (steps, noise, values near the float range, denormals, a prediction
// that is wrong or not finite), in integer and float domains alike.

#include "pipeline/Error.h"
#include "pipeline/QualityMetrics.h"
#include "pipeline/ResidualLayer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>

namespace gvr {
namespace {

/// Dims not multiples of a block or a slab, so that partial blocks and slabs are met.
const openvdb::Coord kOddDims(19, 13, 37);

FloatVolume layerVolume(int channels, const std::function<float(int, int, int, int)>& value) {
    FloatVolume v(kOddDims, channels);
    for (int k = 0; k < kOddDims.z(); ++k)
        for (int j = 0; j < kOddDims.y(); ++j)
            for (int i = 0; i < kOddDims.x(); ++i)
                for (int c = 0; c < channels; ++c) v.at(i, j, k)[c] = value(i, j, k, c);
    return v;
}

/// Steps, noise and smooth ramps side by side, on stored samples intercept + slope * k.
FloatVolume adversarialIntegers(double slope, double intercept, int channels = 1) {
    std::mt19937 random(7);
    std::uniform_int_distribution<int> noise(-300, 300);
    return layerVolume(channels, [&](int i, int j, int k, int c) {
        int sample = i < 6 ? 0 : i < 12 ? 2000 : noise(random);  // air, a step, noise
        if (j > 9) sample = 3 * k + c;                           // a ramp
        return float(intercept + slope * sample);
    });
}

/// A prediction that is right in places, off by a smooth error, and far off elsewhere.
FloatVolume roughPrediction(const FloatVolume& source) {
    FloatVolume p = source;
    for (std::size_t n = 0; n < p.values.size(); ++n) p.values[n] += float(17.0 * std::sin(0.1 * double(n)));
    for (std::size_t n = 0; n < p.values.size(); n += 11) p.values[n] = 0.0f;
    return p;
}

double roundTripError(const FloatVolume& source, const FloatVolume& prediction, double bound,
                      const ResidualDomain& domain, ResidualLayer* out = nullptr) {
    const ResidualLayer layer = encodeResidualLayer(source, prediction, bound, domain);
    const FloatVolume decoded = decodeResidualLayer(layer, prediction);
    if (out) *out = layer;
    return maxAbsoluteError(source, decoded);
}

TEST(ResidualLayer, IntegerDataIsWithinTheBoundAndLosslessAtZero) {
    const FloatVolume source = adversarialIntegers(1.0, -1024.0);
    const ResidualDomain domain = residualDomainOf(source, 1.0, -1024.0);
    ASSERT_TRUE(domain.integers);
    const FloatVolume prediction = roughPrediction(source);
    for (double bound : {0.0, 0.5, 1.0, 4.0, 100.0}) {
        EXPECT_LE(roundTripError(source, prediction, bound, domain), std::floor(bound)) << "bound " << bound;
    }
    EXPECT_EQ(roundTripError(source, prediction, 0.0, domain), 0.0);
}

TEST(ResidualLayer, IntegerReconstructionsAreWholeStoredSamples) {
    // A slope of 0.5: the file's own type holds only intercept + 0.5 k.
    const FloatVolume source = adversarialIntegers(0.5, 3.0);
    const ResidualDomain domain = residualDomainOf(source, 0.5, 3.0);
    ASSERT_TRUE(domain.integers);
    const FloatVolume prediction = roughPrediction(source);
    const ResidualLayer layer = encodeResidualLayer(source, prediction, 1.3, domain);
    EXPECT_EQ(layer.step(), 5.0);  // 1.3 is two whole samples of 0.5 either way: 2 * 2 + 1
    const FloatVolume decoded = decodeResidualLayer(layer, prediction);
    for (float v : decoded.values) EXPECT_EQ(std::fmod(double(v) - 3.0, 0.5), 0.0);
    EXPECT_LE(maxAbsoluteError(source, decoded), 1.0);
}

TEST(ResidualLayer, FloatDataHoldsTheBoundAfterRoundingNearTheFloatRange) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const FloatVolume source = layerVolume(1, [&](int i, int j, int k, int) {
        if (i < 3) return j % 2 ? 3e38f : -3e38f;            // the float range's edge, alternating
        if (i < 6) return FLT_TRUE_MIN * float(j + 1);       // denormals
        if (i < 9) return 1e6f + unit(random);               // fine detail on a large offset
        return float(k) * 0.37f + (j > 6 ? 1000.0f : 0.0f);  // a ramp with a step
    });
    ASSERT_FALSE(residualDomainOf(source, 1.0, 0.0).integers);
    const FloatVolume prediction = roughPrediction(source);
    for (double bound : {1e-30, 1e-3, 0.5, 1e3}) {
        ResidualLayer layer;
        EXPECT_LE(roundTripError(source, prediction, bound, {}, &layer), bound) << "bound " << bound;
    }
}

TEST(ResidualLayer, FloatDataNearTheFloatRangeIsCodedNotStoredExactly) {
    std::mt19937 random(5);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    const FloatVolume source = layerVolume(1, [&](int i, int, int, int) { return (i + noise(random)) * 5e36f; });
    const FloatVolume prediction = roughPrediction(source);
    ResidualLayer layer;
    EXPECT_LE(roundTripError(source, prediction, 1e36, {}, &layer), 1e36);
    EXPECT_LT(layer.exactVoxels(), source.voxelCount() / 100);  // predictions of 1e38 are predictions too
}

TEST(ResidualLayer, APredictionThatIsNotFiniteOrFarOffStillGivesTheBound) {
    const FloatVolume source = adversarialIntegers(1.0, 0.0);
    FloatVolume prediction = source;
    for (std::size_t n = 0; n < prediction.values.size(); ++n) {
        prediction.values[n] = n % 3 == 0 ? INFINITY : n % 3 == 1 ? -3e38f : NAN;
    }
    const ResidualDomain domain = residualDomainOf(source, 1.0, 0.0);
    EXPECT_LE(roundTripError(source, prediction, 2.0, domain), 2.0);
}

TEST(ResidualLayer, ColourChannelsEachHoldTheBound) {
    const FloatVolume source = adversarialIntegers(1.0, 0.0, 3);
    const ResidualDomain domain = residualDomainOf(source, 1.0, 0.0);
    EXPECT_LE(roundTripError(source, roughPrediction(source), 0.5, domain), 0.0);
    EXPECT_LE(roundTripError(source, roughPrediction(source), 3.0, domain), 3.0);
}

TEST(ResidualLayer, AirIsPredictedFromItsNeighboursAndDetailFromTheGaussians) {
    // Air at -1000 exactly, where the Gaussians leave tails; a structure the Gaussians know.
    const FloatVolume source = layerVolume(1, [](int i, int j, int k, int) {
        return i < 8 ? -1000.0f : float(std::round(500.0 * std::sin(0.9 * i) * std::cos(0.7 * j + 0.3 * k)));
    });
    FloatVolume prediction = source;
    for (int k = 0; k < kOddDims.z(); ++k)
        for (int j = 0; j < kOddDims.y(); ++j)
            for (int i = 0; i < kOddDims.x(); ++i)
                *prediction.at(i, j, k) += i < 8 ? float(7 * ((i + j + k) % 5)) : 0.25f;
    const ResidualDomain domain = residualDomainOf(source, 1.0, 0.0);
    const ResidualLayer layer = encodeResidualLayer(source, prediction, 0.0, domain);
    EXPECT_EQ(layer.predictors[0], ResidualPredictor::Neighbours);  // block (0, 0, 0): all air
    EXPECT_EQ(layer.predictors[2], ResidualPredictor::Gaussians);   // block (2, 0, 0): detail alone
    EXPECT_EQ(maxAbsoluteError(source, decodeResidualLayer(layer, prediction)), 0.0);
}

TEST(ResidualLayer, ReconstructionsStayWithinTheSourceRange) {
    // uint8-like samples 0..254 and a wide step: unclamped, a step past 0 or 254 gives
    // values the source's type cannot hold (and a NIfTI writer would clamp).
    std::mt19937 random(4);
    std::uniform_int_distribution<int> sample(0, 254);
    const FloatVolume source = layerVolume(1, [&](int i, int, int, int) { return float(i < 9 ? 0 : sample(random)); });
    const ResidualDomain domain = residualDomainOf(source, 1.0, 0.0);
    const FloatVolume prediction = roughPrediction(source);
    const FloatVolume decoded = decodeResidualLayer(encodeResidualLayer(source, prediction, 6.0, domain), prediction);
    EXPECT_LE(maxAbsoluteError(source, decoded), 6.0);
    EXPECT_EQ(*std::min_element(decoded.values.begin(), decoded.values.end()), 0.0f);
    EXPECT_LE(*std::max_element(decoded.values.begin(), decoded.values.end()), 254.0f);
}

TEST(ResidualLayer, ABadBoundIsRefusedInOneLine) {
    const FloatVolume floats = layerVolume(1, [](int i, int, int, int) { return 0.1f * float(i); });
    const FloatVolume integers = adversarialIntegers(1.0, 0.0);
    const ResidualDomain integerDomain = residualDomainOf(integers, 1.0, 0.0);
    for (double bad : {double(NAN), -1.0, double(INFINITY)}) {
        EXPECT_THROW(encodeResidualLayer(integers, integers, bad, integerDomain), InputError) << bad;
    }
    try {
        encodeResidualLayer(floats, floats, 0.0, {});
        FAIL() << "a zero bound on float data was accepted";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("lossless"), std::string::npos) << error.what();
    }
    EXPECT_NO_THROW(encodeResidualLayer(integers, integers, 0.0, integerDomain));
}

TEST(ResidualLayer, ADomainNeedsEveryVoxelOnTheStoredSamples) {
    FloatVolume v = adversarialIntegers(1.0, -1024.0);
    EXPECT_TRUE(residualDomainOf(v, 1.0, -1024.0).integers);
    v.values[100] += 0.5f;  // an ingested grid's background, -986.5, between two samples
    EXPECT_FALSE(residualDomainOf(v, 1.0, -1024.0).integers);
    EXPECT_FALSE(residualDomainOf(adversarialIntegers(1.0, 0.0), 0.0, 0.0).integers);
}

}  // namespace
}  // namespace gvr
