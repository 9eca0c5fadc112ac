// The slice stack's run-length encoding: what compositing relies on to skip
// empty space, including the hollows inside a body.

#include "SliceStack.h"
#include "TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

/// A hollow ball: a shell of radius 12 voxels, empty inside and out.
GridRenderVolume hollowBall() {
    return GridRenderVolume(test::makeGrid({40, 40, 40}, [](int i, int j, int k) {
        const double r = std::sqrt((i - 20.0) * (i - 20.0) + (j - 20.0) * (j - 20.0) + (k - 20.0) * (k - 20.0));
        return float(1000.0 * std::exp(-std::pow((r - 12.0) / 1.5, 2.0)));
    }));
}

TEST(SliceStack, RowsKeepOnlyTheirRunsOfVisibleSamples) {
    const GridRenderVolume ball = hollowBall();
    const Classifier classifier(TransferFunction({{100.0, {1, 1, 1, 0}}, {1000.0, {1, 1, 1, 0.5f}}}, "test"), 1);
    const SliceStack stack(ball, classifier, openvdb::Vec3d(0.3, 0.2, 1.0), 1.0, 1.0);
    std::size_t rowsWithAHollow = 0, runs = 0;
    for (const Slice& slice : stack.slices()) {
        ASSERT_EQ(slice.rowRuns.size(), std::size_t(stack.geometry().height) + 1);
        for (int j = 0; j < stack.geometry().height; ++j) {
            const std::uint32_t first = slice.rowRuns[j], end = slice.rowRuns[j + 1];
            rowsWithAHollow += end - first >= 2;
            for (std::uint32_t r = first; r < end; ++r) {
                const RowRun& run = slice.runs[r];
                ++runs;
                ASSERT_LT(run.begin, run.end);
                ASSERT_LE(run.end, std::uint32_t(stack.geometry().width));
                // A run starts and ends on a visible sample, and only gaps of at least
                // kRunGap transparent samples separate runs.
                EXPECT_GT(slice.samples[run.offset].a, 0);
                EXPECT_GT(slice.samples[run.offset + run.end - run.begin - 1].a, 0);
                if (r > first) EXPECT_GE(run.begin - slice.runs[r - 1].end, std::uint32_t(kRunGap));
                // Each run lies between two transparent samples.
                EXPECT_EQ(slice.samples[run.offset - 1].a, 0);
                EXPECT_EQ(slice.samples[run.offset + run.end - run.begin].a, 0);
                if (r + 1 < end) EXPECT_EQ(slice.runs[r + 1].offset, run.offset + run.end - run.begin + 2);
            }
        }
    }
    EXPECT_GT(runs, 0u);
    // Rows through the middle of the ball cross the shell twice.
    EXPECT_GT(rowsWithAHollow, 100u);
}

}  // namespace
}  // namespace gvr
