// Quality per labelled structure: each structure's error is its own, voxels of
// other structures inside its box count for nothing, and absent ids give zeros.

#include "pipeline/StructureQuality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace gvr {
namespace {

const openvdb::Coord kDims(8, 6, 4);

FloatVolume rampVolume() {
    FloatVolume v(kDims, 1);
    for (int k = 0; k < kDims.z(); ++k) {
        for (int j = 0; j < kDims.y(); ++j) {
            for (int i = 0; i < kDims.x(); ++i) v.at(i, j, k)[0] = float(i + j + k);
        }
    }
    return v;
}

/// One label per voxel from @a labelOf(i).
std::vector<int> labelsByColumn(int (*labelOf)(int)) {
    const FloatVolume shape(kDims, 1);
    std::vector<int> labels(shape.voxelCount());
    for (int k = 0; k < kDims.z(); ++k) {
        for (int j = 0; j < kDims.y(); ++j) {
            for (int i = 0; i < kDims.x(); ++i) labels[shape.indexOf(i, j, k)] = labelOf(i);
        }
    }
    return labels;
}

TEST(StructureQuality, EachStructureGetsItsOwnErrorInTheOrderAsked) {
    const FloatVolume reference = rampVolume();
    const std::vector<int> labels = labelsByColumn([](int i) { return i < 4 ? 1 : 2; });
    FloatVolume test = reference;
    for (std::size_t n = 0; n < labels.size(); ++n) {
        if (labels[n] == 1) test.values[n] += 2.0f;
    }
    const std::vector<StructureQuality> rows = structureQuality(reference, test, labels, {2, 1, 7}, 100.0);
    ASSERT_EQ(rows.size(), 3u);

    EXPECT_EQ(rows[0].id, 2);
    EXPECT_EQ(rows[0].voxels, 4u * 6u * 4u);
    EXPECT_EQ(rows[0].mse, 0.0);
    EXPECT_TRUE(std::isinf(rows[0].psnr));
    EXPECT_NEAR(rows[0].ssim, 1.0, 1e-9);

    EXPECT_EQ(rows[1].id, 1);
    EXPECT_EQ(rows[1].voxels, 4u * 6u * 4u);
    EXPECT_DOUBLE_EQ(rows[1].mse, 4.0);
    EXPECT_NEAR(rows[1].psnr, 20.0 * std::log10(100.0) - 10.0 * std::log10(4.0), 1e-9);
    EXPECT_LT(rows[1].ssim, 0.999);  // a shifted mean lowers SSIM's luminance term
}

TEST(StructureQuality, AnAbsentIdGivesAZeroRow) {
    const FloatVolume reference = rampVolume();
    const std::vector<int> labels(reference.voxelCount(), 1);
    const std::vector<StructureQuality> rows = structureQuality(reference, reference, labels, {7}, 100.0);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].id, 7);
    EXPECT_EQ(rows[0].voxels, 0u);
    EXPECT_EQ(rows[0].mse, 0.0);
    EXPECT_EQ(rows[0].psnr, 0.0);
    EXPECT_EQ(rows[0].ssim, 0.0);
    EXPECT_TRUE(structureQuality(reference, reference, labels, {}, 100.0).empty());
}

TEST(StructureQuality, OtherStructuresInsideTheBoxAreCutOut) {
    // Interleaved columns: structure 1's box holds all of structure 2, whose errors
    // are huge and must not leak into structure 1's MSE or SSIM.
    const FloatVolume reference = rampVolume();
    const std::vector<int> labels = labelsByColumn([](int i) { return i % 2 == 0 ? 1 : 2; });
    FloatVolume test = reference;
    for (std::size_t n = 0; n < labels.size(); ++n) {
        if (labels[n] == 2) test.values[n] = 1000.0f;
    }
    const std::vector<StructureQuality> rows = structureQuality(reference, test, labels, {1, 2}, 100.0);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].voxels, 4u * 6u * 4u);
    EXPECT_EQ(rows[0].mse, 0.0);
    EXPECT_NEAR(rows[0].ssim, 1.0, 1e-9);
    EXPECT_GT(rows[1].mse, 800.0 * 800.0);
    EXPECT_LT(rows[1].psnr, 0.0);  // errors beyond the peak give a negative PSNR
}

}  // namespace
}  // namespace gvr
