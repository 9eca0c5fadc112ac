// How many Gaussians each structure gets: exactly the total, floors first, the
// rest by voxels; and a budget per voxel that depends on each structure alone.

#include "pipeline/Error.h"
#include "pipeline/LabelBudget.h"

#include <gtest/gtest.h>

#include <numeric>

namespace gvr {
namespace {

TEST(LabelBudget, SplitAddsUpToTheTotalWithAFloor) {
    const std::vector<std::uint64_t> voxels = {100000, 5000, 3, 800};
    for (std::size_t total : {51u, 52u, 1000u, 12345u}) {  // the floors take 16 + 16 + 3 + 16
        const std::vector<std::size_t> budget = splitBudget(total, voxels);
        EXPECT_EQ(std::accumulate(budget.begin(), budget.end(), std::size_t(0)), total);
        EXPECT_GE(budget[1], kStructureFloor);
        EXPECT_GE(budget[2], 3u);         // a 3-voxel structure's floor is its voxels
        EXPECT_GE(budget[0], budget[1]);  // proportional above the floor
    }
    const std::vector<std::size_t> big = splitBudget(100000, voxels);
    EXPECT_NEAR(double(big[0]) / double(big[1]), 20.0, 0.5);
    EXPECT_THROW(splitBudget(50, voxels), InputError);  // cannot cover the 51 of the floors
}

TEST(LabelBudget, ProportionalBudgetsDependOnEachStructureAlone) {
    const std::vector<std::size_t> both = proportionalBudgets(0.01, {100000, 900});
    const std::vector<std::size_t> one = proportionalBudgets(0.01, {100000});
    EXPECT_EQ(both[0], 1000u);
    EXPECT_EQ(both[0], one[0]);
    EXPECT_EQ(both[1], kStructureFloor);               // 9 by proportion, raised to the floor
    EXPECT_EQ(proportionalBudgets(0.01, {5})[0], 5u);  // never more than its voxels by the floor
}

}  // namespace
}  // namespace gvr
