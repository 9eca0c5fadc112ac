// The dense error that fit reports: export's evaluation, summed exactly.

#include "pipeline/FieldAccuracy.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

float ramp(int i, int j, int k) { return float(i * 7 + j * 3 - k * 5 + 40) * (i > 3 ? 1.0f : 0.0f); }

/// The definition, voxel by voxel through GaussianField::evaluate.
SliceSums pointByPoint(const GaussianField& field, const VolumeTarget& target, const openvdb::CoordBBox& box,
                       const ThresholdCut& cut) {
    SliceSums total;
    std::vector<std::uint32_t> hits;
    for (auto ijk = box.begin(); ijk; ++ijk) {
        const float point[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        float value[1], expected[1];
        field.evaluate(point, value, hits);
        cut.apply(value);
        target.valueAt(*ijk, expected);
        const double squared = double(value[0] - expected[0]) * (value[0] - expected[0]);
        total.all += squared;
        if (target.isActive(*ijk)) {
            total.foreground += squared;
            ++total.foregroundVoxels;
        }
    }
    return total;
}

TEST(FieldAccuracy, BlockByBlockEqualsPointByPointWithAndWithoutTheCut) {
    // 21 x 19 x 13 voxels: no axis is a multiple of the 8^3 blocks.
    const VolumeTarget target(test::makeGrid({21, 19, 13}, ramp, openvdb::Vec3d(1.0), 30.0), "ramp");
    const GaussianField field(test::randomGaussians(60, 1, 20.0f, 4), 3.0f);
    const openvdb::CoordBBox part(openvdb::Coord(2, 3, 1), openvdb::Coord(17, 18, 11));
    for (const ThresholdCut& cut : {ThresholdCut(), ThresholdCut(target.mapping(), 1, 60.0)}) {
        const std::vector<SliceSums> slices = measureSliceSums(field, target, part, {}, {}, cut);
        ASSERT_EQ(slices.size(), 11u);
        SliceSums total;
        for (const SliceSums& slice : slices) total.add(slice);
        const SliceSums expected = pointByPoint(field, target, part, cut);
        EXPECT_NEAR(total.all, expected.all, 1e-9 * std::max(1.0, expected.all));
        EXPECT_NEAR(total.foreground, expected.foreground, 1e-9 * std::max(1.0, expected.foreground));
        EXPECT_EQ(total.foregroundVoxels, expected.foregroundVoxels);
        EXPECT_GT(expected.foregroundVoxels, 0.0);
    }
    // The cut changes the number on these data: the test can tell the two apart.
    const double uncut = measureFieldAccuracy(field, target).mse;
    const double cut = measureFieldAccuracy(field, target, {}, {}, ThresholdCut(target.mapping(), 1, 60.0)).mse;
    EXPECT_NE(uncut, cut);
}

}  // namespace
}  // namespace gvr
