// Box averages: each coarse sample is the mean of its box, boxes at the far edges
// hold what is left, and axes with a factor of 1 keep their samples.

#include "pipeline/BoxAverage.h"

#include <gtest/gtest.h>

#include <vector>

namespace gvr {
namespace {

struct Averaged {
    openvdb::Coord dims;
    std::vector<double> means;
    double at(int i, int j, int k) const { return means[(std::size_t(k) * dims.y() + j) * dims.x() + i]; }
};

/// Box averages of the fine samples value(x, y, z) = x + 10 y + 100 z.
Averaged averagesOf(const openvdb::Coord& coarse, const openvdb::Coord& factor, const openvdb::Coord& fine) {
    Averaged out{coarse, std::vector<double>(std::size_t(coarse.x()) * coarse.y() * coarse.z(), -1.0)};
    forEachBoxAverage(
        coarse, factor, fine, 1, [](int x, int y, int z, double* sums) { sums[0] += x + 10.0 * y + 100.0 * z; },
        [&](int i, int j, int k, const double* means) {
            out.means[(std::size_t(k) * coarse.y() + j) * coarse.x() + i] = means[0];
        });
    return out;
}

TEST(BoxAverage, EachCoarseSampleIsTheMeanOfItsBox) {
    const Averaged a = averagesOf({2, 2, 2}, {2, 2, 2}, {4, 4, 4});
    // Box (1, 0, 1) holds x in {2, 3}, y in {0, 1}, z in {2, 3}: means 2.5, 0.5, 2.5.
    EXPECT_DOUBLE_EQ(a.at(1, 0, 1), 2.5 + 10 * 0.5 + 100 * 2.5);
    EXPECT_DOUBLE_EQ(a.at(0, 0, 0), 0.5 + 10 * 0.5 + 100 * 0.5);
}

TEST(BoxAverage, BoxesAtTheFarEdgeAverageWhatIsLeft) {
    const Averaged a = averagesOf({2, 1, 1}, {3, 3, 3}, {4, 3, 3});
    // The second box along x holds only x = 3.
    EXPECT_DOUBLE_EQ(a.at(1, 0, 0), 3.0 + 10 * 1.0 + 100 * 1.0);
}

TEST(BoxAverage, AFactorOfOneKeepsThatAxis) {
    const Averaged a = averagesOf({2, 3, 1}, {2, 1, 2}, {4, 3, 2});
    for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(a.at(1, j, 0), 2.5 + 10.0 * j + 100 * 0.5) << j;
}

TEST(BoxAverage, EveryChannelIsAveraged) {
    std::vector<double> stored;
    forEachBoxAverage(
        openvdb::Coord(1), openvdb::Coord(2), openvdb::Coord(2), 3,
        [](int x, int, int, double* sums) {
            for (int c = 0; c < 3; ++c) sums[c] += (c + 1) * x;
        },
        [&](int, int, int, const double* means) { stored.assign(means, means + 3); });
    EXPECT_EQ(stored, (std::vector<double>{0.5, 1.0, 1.5}));
}

}  // namespace
}  // namespace gvr
