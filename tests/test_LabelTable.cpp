// Choosing structures by id or name, and splitting the Gaussian budget among them.

#include "pipeline/Error.h"
#include "pipeline/LabelTable.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

using namespace gvr;

namespace {

LabelTable aal() {
    LabelTable table;
    table.names = {{37, "Hippocampus_L"}, {38, "Hippocampus_R"}, {77, "Thalamus_L"}, {78, "Thalamus_R"}};
    return table;
}

std::string selectionError(const std::string& spec) {
    return test::errorMessageOf<InputError>([&] { selectLabels(aal(), spec, "`labels`"); });
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
    const std::string byName = selectionError("Amygdala_L");
    EXPECT_NE(byName.find("`labels`: no structure is named 'Amygdala_L'"), std::string::npos) << byName;
    EXPECT_NE(byName.find("37 Hippocampus_L, 38 Hippocampus_R, 77 Thalamus_L, 78 Thalamus_R"), std::string::npos);
    EXPECT_NE(selectionError("37,99").find("no structure has label 99; valid: 37 Hippocampus_L"), std::string::npos);
    EXPECT_NE(selectionError(" , ").find("names no structure"), std::string::npos);
}
