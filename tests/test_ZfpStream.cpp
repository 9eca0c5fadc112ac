// zfp streams, the reference codec's container: what goes in comes back within the
// tolerance, a rate sets the size, and a damaged file is named, never decoded.

#include "pipeline/Error.h"
#include "tests/TestHelpers.h"
#include "workflow/ZfpStream.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

/// Hounsfield-like values, negative included, on an anisotropic 20 x 12 x 9 box.
FloatVolume ramps(int channels) {
    FloatVolume volume({20, 12, 9}, channels);
    for (int k = 0; k < 9; ++k) {
        for (int j = 0; j < 12; ++j) {
            for (int i = 0; i < 20; ++i) {
                for (int c = 0; c < channels; ++c) {
                    volume.at(i, j, k)[c] = float(-1000.0 + 40.0 * i + 300.0 * std::sin(0.5 * j + c) + 7.0 * k * k);
                }
            }
        }
    }
    return volume;
}

float largestError(const FloatVolume& a, const FloatVolume& b) {
    float largest = 0.0f;
    for (std::size_t n = 0; n < a.values.size(); ++n) largest = std::max(largest, std::abs(a.values[n] - b.values[n]));
    return largest;
}

TEST(ZfpStream, AccuracyModeHonoursItsToleranceExactly) {
    test::TempDir dir;
    for (int channels : {1, 3}) {
        const FloatVolume source = ramps(channels);
        for (double tolerance : {0.5, 3.0, 25.0}) {
            double effective = 0.0;
            writeZfpFile(dir.path("v.zfp"), encodeZfp(source, {ZfpMode::FixedAccuracy, tolerance}, &effective));
            const FloatVolume back = readZfpFile(dir.path("v.zfp"));
            EXPECT_EQ(back.dims, source.dims);
            EXPECT_EQ(back.channels, channels);
            EXPECT_LE(largestError(source, back), tolerance) << channels << " channels, tolerance " << tolerance;
            EXPECT_GT(largestError(source, back), 0.0f);  // lossy: something was dropped
        }
    }
}

TEST(ZfpStream, ARateSetsTheSize) {
    const FloatVolume source = ramps(1);
    const std::size_t four = encodeZfp(source, {ZfpMode::FixedRate, 4.0}).size();
    const std::size_t sixteen = encodeZfp(source, {ZfpMode::FixedRate, 16.0}).size();
    // 20 x 12 x 9 pads to 5 x 3 x 3 blocks of 64 values.
    const double values = 5.0 * 3 * 3 * 64;
    EXPECT_NEAR(double(sixteen - four), values * 12.0 / 8.0, 64.0);
}

TEST(ZfpStream, ADamagedFileIsNamedAndNotDecoded) {
    test::TempDir dir;
    const std::string good = dir.path("good.zfp"), cut = dir.path("cut.zfp"), foreign = dir.path("foreign.zfp");
    writeZfpFile(good, encodeZfp(ramps(1), {ZfpMode::FixedAccuracy, 1.0}));
    test::copyTruncated(good, cut, 60);
    std::string bytes = test::readBytes(good);
    bytes[0] = 'X';
    test::writeBytes(foreign, bytes);
    for (const std::string& path : {cut, foreign}) {
        const std::string message = test::errorMessageOf<InputError>([&] { readZfpFile(path); });
        EXPECT_NE(message.find(path), std::string::npos) << message;
    }
}

}  // namespace
}  // namespace gvr
