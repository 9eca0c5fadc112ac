// Fitting by structure: voxels counted per label (tiles included), each chosen
// structure fitted on its own with a seed of its own, and the Gaussians labelled.

#include "pipeline/LabelledFit.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace gvr {
namespace {

FitSettings quickSettings(std::size_t iterations) {
    FitSettings settings;
    settings.iterations = iterations;
    settings.seconds = 0.0;
    settings.voxelBatch = 1024;
    settings.slicePixels = 256;
    settings.heldOutVoxels = 256;
    settings.logEvery = 5;
    settings.pruneEvery = 50;
    return settings;
}

/// Label 1 on a 5^3 box of single voxels, label 2 on a whole 8^3 leaf stored as a tile.
openvdb::Int32Grid::Ptr twoStructures() {
    openvdb::Int32Grid::Ptr labels = openvdb::Int32Grid::create(0);
    labels->tree().fill(openvdb::CoordBBox(openvdb::Coord(1, 1, 1), openvdb::Coord(5, 5, 5)), 1, true);
    labels->tree().fill(openvdb::CoordBBox(openvdb::Coord(8, 0, 0), openvdb::Coord(15, 7, 7)), 2, true);
    return labels;
}

TEST(LabelledFit, VoxelsAreCountedPerLabelTilesIncluded) {
    openvdb::Int32Grid::Ptr labels = twoStructures();
    labels->tree().setValueOn(openvdb::Coord(-4, -4, -4), -2);  // negative ids are labels too
    labels->tree().setValueOn(openvdb::Coord(30, 0, 0), -2);
    ASSERT_GT(labels->tree().activeTileCount(), 0u) << "the 8^3 fill should be a tile";
    const std::vector<std::uint64_t> counts = countLabelVoxels(*labels, {2, 1, 42, -2});
    EXPECT_EQ(counts, (std::vector<std::uint64_t>{512, 125, 0, 2}));
    EXPECT_TRUE(countLabelVoxels(*labels, {}).empty());
}

TEST(LabelledFit, EachStructureIsFittedAloneAndTheSameWhateverIsFittedBesideIt) {
    const auto image = test::makeGrid({20, 12, 12}, [](int i, int j, int k) { return float(10 + i + 2 * j + 3 * k); });
    const openvdb::Int32Grid::Ptr labels = twoStructures();
    const FitSettings settings = quickSettings(10);

    std::size_t lastIteration = 0;
    const LabelledFitResult all = fitStructures(*image, *labels, {{1, 0, 6, {}}, {2, 0, 5, {}}, {7, 0, 4, {}}},
                                                settings, [&](const FitProgress& p) { lastIteration = p.iteration; });
    ASSERT_EQ(all.structures.size(), 3u);
    EXPECT_EQ(all.structures[0].voxels, 125u);
    EXPECT_EQ(all.structures[1].voxels, 512u);
    EXPECT_EQ(all.structures[2].voxels, 0u);  // id 7 is not in the label grid: no Gaussians, no fit
    EXPECT_EQ(all.structures[0].report.iterations, 10u);
    EXPECT_EQ(all.structures[2].report.iterations, 0u);
    EXPECT_EQ(lastIteration, 20u);  // the observer sees iterations summed over structures
    ASSERT_EQ(all.labels.size(), all.params.count());
    EXPECT_TRUE(std::is_sorted(all.labels.begin(), all.labels.end()));  // grouped in structure order
    const std::size_t ones = std::size_t(std::count(all.labels.begin(), all.labels.end(), 1));
    ASSERT_GT(ones, 0u);
    EXPECT_GT(all.labels.size(), ones);
    EXPECT_EQ(std::count(all.labels.begin(), all.labels.end(), 7), 0);

    // Structure 1 with no budget is skipped; structure 2 comes out as it did beside 1 and 7.
    const LabelledFitResult alone = fitStructures(*image, *labels, {{1, 0, 0, {}}, {2, 0, 5, {}}}, settings);
    EXPECT_EQ(alone.structures[0].voxels, 125u);
    ASSERT_EQ(alone.params.count(), all.params.count() - ones);
    EXPECT_TRUE(std::all_of(alone.labels.begin(), alone.labels.end(), [](int id) { return id == 2; }));
    for (int g = 0; g < kGroupCount; ++g) {
        const std::size_t width = std::size_t(all.params.width(ParameterGroup(g)));
        const std::vector<float> tail(all.params.values[g].begin() + std::ptrdiff_t(ones * width),
                                      all.params.values[g].end());
        EXPECT_EQ(tail, alone.params.values[g]) << groupName(ParameterGroup(g));
    }
}

}  // namespace
}  // namespace gvr
