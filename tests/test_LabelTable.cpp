// Choosing structures by id or name, and splitting the Gaussian budget among them.

#include "pipeline/Error.h"
#include "pipeline/LabelBudget.h"
#include "pipeline/LabelTable.h"

#include <gtest/gtest.h>

#include <numeric>

using namespace gvr;

namespace {

LabelTable aal() {
    LabelTable table;
    table.names = {{37, "Hippocampus_L"}, {38, "Hippocampus_R"}, {77, "Thalamus_L"}, {78, "Thalamus_R"}};
    return table;
}

std::string errorOf(const std::string& spec) {
    try {
        selectLabels(aal(), spec, "`labels`");
    } catch (const InputError& error) {
        return error.what();
    }
    return "";
}

}  // namespace

TEST(LabelTable, SelectsByIdNameAndAll) {
    EXPECT_EQ(selectLabels(aal(), "all", "x"), (std::vector<int>{37, 38, 77, 78}));
    EXPECT_EQ(selectLabels(aal(), "77, Hippocampus_L,hippocampus_r", "x"), (std::vector<int>{37, 38, 77}));
    EXPECT_EQ(shownLabels(aal(), "", "Thalamus_L,38"), (std::vector<int>{37, 78}));
    EXPECT_EQ(shownLabels(aal(), "37,38", ""), (std::vector<int>{37, 38}));
    EXPECT_EQ(aal().nameOf(5), "label_5");
}

TEST(LabelTable, UnknownNamesAndIdsListTheValidOnes) {
    const std::string byName = errorOf("Amygdala_L");
    EXPECT_NE(byName.find("`labels`: no structure is named 'Amygdala_L'"), std::string::npos) << byName;
    EXPECT_NE(byName.find("37 Hippocampus_L, 38 Hippocampus_R, 77 Thalamus_L, 78 Thalamus_R"), std::string::npos);
    EXPECT_NE(errorOf("37,99").find("no structure has label 99; valid: 37 Hippocampus_L"), std::string::npos);
    EXPECT_NE(errorOf(" , ").find("names no structure"), std::string::npos);
}

TEST(LabelBudget, SplitAddsUpToTheTotalWithAFloor) {
    const std::vector<std::uint64_t> voxels = {100000, 5000, 3, 800};
    for (std::size_t total : {51u, 52u, 1000u, 12345u}) {  // the floors take 16 + 16 + 3 + 16
        const std::vector<std::size_t> budget = splitBudget(total, voxels);
        EXPECT_EQ(std::accumulate(budget.begin(), budget.end(), std::size_t(0)), total);
        EXPECT_GE(budget[1], kStructureFloor);
        EXPECT_GE(budget[2], 3u);  // a 3-voxel structure's floor is its voxels
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
    EXPECT_EQ(both[1], kStructureFloor);  // 9 by proportion, raised to the floor
    EXPECT_EQ(proportionalBudgets(0.01, {5})[0], 5u);  // never more than its voxels by the floor
}
