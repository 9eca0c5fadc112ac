// The block kernel: the rows it visits are those the ellipsoid crosses, and along
// each the parabola gives q as the quadratic does, in four lanes.

#include "pipeline/BlockKernel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

namespace gvr {
namespace {

/// An oblique ellipsoid whose centre lies inside the block at (3.2, 4.7, 2.9).
BlockQuadratic obliqueQuadratic() {
    const double centre[3] = {3.2, 4.7, 2.9};
    BlockQuadratic quad{{{0.30, 0.08, -0.05}, {0.08, 0.45, 0.11}, {-0.05, 0.11, 0.60}}, {0, 0, 0}, 0};
    // q = (r - c)^T G (r - c) = h + 2 gLin.r + r^T G r with gLin = -G c and h = c^T G c.
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            quad.gLin[a] -= quad.G[a][b] * centre[b];
            quad.h += centre[a] * quad.G[a][b] * centre[b];
        }
    }
    return quad;
}

double qAt(const BlockQuadratic& quad, const double r[3]) {
    double q = quad.h;
    for (int a = 0; a < 3; ++a) {
        q += 2.0 * quad.gLin[a] * r[a];
        for (int b = 0; b < 3; ++b) q += r[a] * quad.G[a][b] * r[b];
    }
    return q;
}

/// The least q along row (x, y), by sampling z finely.
double leastQAlongRow(const BlockQuadratic& quad, int x, int y) {
    double least = HUGE_VAL;
    for (int step = -4000; step <= 12000; ++step) {
        const double r[3] = {double(x), double(y), step * 1e-3};
        least = std::min(least, qAt(quad, r));
    }
    return least;
}

TEST(BlockKernel, VisitsExactlyTheRowsTheEllipsoidCrosses) {
    const BlockQuadratic quad = obliqueQuadratic();
    const float cutoff2 = 2.5f;
    std::set<std::pair<int, int>> visited;
    forEachRowCrossed(
        quad, 0, kBlockDim - 1, [](int) { return 0; }, kBlockDim - 1, 1, cutoff2,
        [&](int x, int y, const RowParabola&) {
            visited.insert({x, y});
        });
    int crossed = 0;
    for (int x = 0; x < kBlockDim; ++x) {
        for (int y = 0; y < kBlockDim; ++y) {
            const double least = leastQAlongRow(quad, x, y);
            if (std::abs(least - cutoff2) < 1e-3) continue;  // too close to call by sampling
            const bool crosses = least <= cutoff2;
            crossed += crosses;
            EXPECT_EQ(visited.count({x, y}) == 1, crosses) << x << ", " << y;
        }
    }
    EXPECT_GT(crossed, 4);
    EXPECT_LT(crossed, kBlockDim * kBlockDim);
}

TEST(BlockKernel, RowsStartWhereFirstYSaysAndStepByTheStride) {
    const BlockQuadratic quad = obliqueQuadratic();
    std::set<std::pair<int, int>> visited;
    forEachRowCrossed(
        quad, 0, kBlockDim - 1, [](int x) { return x % 3; }, kBlockDim - 1, 3, 1e30f,
        [&](int x, int y, const RowParabola&) {
            visited.insert({x, y});
        });
    for (int x = 0; x < kBlockDim; ++x) {
        for (int y = 0; y < kBlockDim; ++y) {
            const bool sampled = y >= x % 3 && (y - x % 3) % 3 == 0;
            EXPECT_EQ(visited.count({x, y}) == 1, sampled) << x << ", " << y;
        }
    }
}

TEST(BlockKernel, RowQGivesTheQuadraticAtEverySampleOfTheRow) {
    const BlockQuadratic quad = obliqueQuadratic();
    int rows = 0;
    forEachRowCrossed(
        quad, 0, kBlockDim - 1, [](int) { return 0; }, kBlockDim - 1, 1, 1e30f,
        [&](int x, int y, const RowParabola& row) {
            ++rows;
            for (int part = 0; part < kBlockDim; part += 4) {
                const Floats4 q = rowQ<Floats4>(row, part);
                for (int i = 0; i < 4; ++i) {
                    const double r[3] = {double(x), double(y), double(part + i)};
                    EXPECT_NEAR(q[i], qAt(quad, r), 1e-5 * (1.0 + qAt(quad, r)));
                }
            }
        });
    EXPECT_EQ(rows, kBlockDim * kBlockDim);
}

TEST(BlockKernel, KernelIsExpOfMinusHalfQWhereKeptAndZeroElsewhere) {
    const Floats4 q = {0.0f, 1.0f, 4.0f, 9.0f};
    const Ints4 keep = {-1, 0, -1, 0};
    const Floats4 e = kernelWhere(q, keep);
    EXPECT_NEAR(e[0], 1.0f, 1e-6f);
    EXPECT_EQ(e[1], 0.0f);
    EXPECT_NEAR(e[2], std::exp(-2.0f), 1e-6f);
    EXPECT_EQ(e[3], 0.0f);
}

}  // namespace
}  // namespace gvr
