// The slice stack's run-length encoding: what compositing relies on to skip
// empty space, including the hollows inside a body, for classified samples and
// for values.

#include "pipeline/Error.h"
#include "pipeline/Luminance.h"
#include "render/Camera.h"
#include "render/ShearWarp.h"
#include "render/SliceStack.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace gvr {
namespace {

/// A shell of radius 12 voxels, empty inside and out, at voxel (i, j, k).
float hollowBallAt(int i, int j, int k) {
    const double r = std::sqrt((i - 20.0) * (i - 20.0) + (j - 20.0) * (j - 20.0) + (k - 20.0) * (k - 20.0));
    return float(1000.0 * std::exp(-std::pow((r - 12.0) / 1.5, 2.0)));
}

GridRenderVolume hollowBall() { return GridRenderVolume(test::makeGrid({40, 40, 40}, hollowBallAt)); }

Classifier shellClassifier() {
    return Classifier(TransferFunction({{100.0, {1, 1, 1, 0}}, {1000.0, {1, 1, 1, 0.5f}}}, "test"), 1);
}

TEST(SliceStack, GreyVolumesKeepValuesAndOtherStacksClassifiedSamples) {
    const GridRenderVolume ball = hollowBall();
    const SliceStack values(ball, shellClassifier(), openvdb::Vec3d(0, 0, 1), 1.0, 1.0);
    EXPECT_EQ(values.content(), StackContent::Values);
    EXPECT_NE(values.valueLevels(), nullptr);
    // Two layers combine their classified samples; so does a visible background,
    // whose values outside the volume would be wrongly seen.
    const SliceStack layered({{&ball, shellClassifier()}, {&ball, shellClassifier()}}, openvdb::Vec3d(0, 0, 1), 1.0,
                             1.0);
    EXPECT_EQ(layered.content(), StackContent::Classified);
    EXPECT_EQ(layered.valueLevels(), nullptr);
    const Classifier fog(TransferFunction({{0.0, {1, 1, 1, 0.01f}}, {1000.0, {1, 1, 1, 0.5f}}}, "test"), 1);
    EXPECT_EQ(SliceStack(ball, fog, openvdb::Vec3d(0, 0, 1), 1.0, 1.0).content(), StackContent::Classified);
}

// A colour volume keeps its colours, and the luminance that classifies them, where
// its samples fall on the voxel centres; elsewhere, classified samples on the
// spacing asked (resampled apart, colour and opacity came out paler).
TEST(SliceStack, ColourVolumesKeepTheirColoursOnTheVoxelCentres) {
    const openvdb::Vec3s paper(250.0f, 240.0f, 230.0f);
    const GridRenderVolume section(test::makeColourGrid(
        {20, 16, 12},
        [&](int i, int j, int k) {
            const float dark = hollowBallAt(i, j, k) / 5.0f;
            return openvdb::Vec3s(paper[0] - dark, paper[1] - 1.2f * dark, paper[2] - 1.1f * dark);
        },
        paper));
    const Classifier darkIsDense(TransferFunction({{50.0, {1, 1, 1, 0.5f}}, {200.0, {1, 1, 1, 0.0f}}}, "test"), 3,
                                 1.0 / 250.0);
    const SliceStack onCentres(section, darkIsDense, openvdb::Vec3d(0, 0, 1), 1.0, 1.0);
    ASSERT_EQ(onCentres.content(), StackContent::Colours);
    ASSERT_TRUE(onCentres.geometry().samplesOnVoxels);
    const ValueLevels& levels = *onCentres.valueLevels();
    int checked = 0;
    for (const Slice& slice : onCentres.slices()) {
        EXPECT_TRUE(slice.codes.empty());
        for (int j = 0; j < onCentres.geometry().height; ++j) {
            for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r) {
                const RowRun& run = slice.runs[r];
                for (std::uint32_t i = run.begin; i < run.end; ++i, ++checked) {
                    // The sample's voxel: its colour, scaled, and its luminance's level.
                    const openvdb::Vec3d index = onCentres.geometry().lattice().worldFromIndex.transform(
                        openvdb::Vec3d(double(i), double(j), double(&slice - onCentres.slices().data())));
                    const openvdb::Coord voxel(int(std::lround(index.x())), int(std::lround(index.y())),
                                               int(std::floor(index.z())));
                    const double below = index.z() - voxel.z();  // slices lie off the voxel planes
                    const auto at = [&](int dz) {
                        return dynamic_cast<const openvdb::Vec3SGrid&>(section.voxels())
                            .getConstAccessor()
                            .getValue(voxel.offsetBy(0, 0, dz));
                    };
                    const openvdb::Vec3s value = at(0) * float(1.0 - below) + at(1) * float(below);
                    const StackSample& sample = slice.samples[run.offset + i - run.begin];
                    EXPECT_NEAR(sample.r, value[0] / 250.0 * 65535.0, 2.0);
                    EXPECT_NEAR(sample.b, value[2] / 250.0 * 65535.0, 2.0);
                    const float level = slice.coding.level(sample.a);
                    EXPECT_NEAR(ValueLevels::nearest(level), levels.levelOf(float(luminance(value))), 1);
                }
            }
        }
    }
    EXPECT_GT(checked, 100);
    // Samples a third of a voxel apart are too far from the centres' spacing.
    const SliceStack offCentres(section, darkIsDense, openvdb::Vec3d(0, 0, 1), 1.0, 0.34);
    EXPECT_EQ(offCentres.content(), StackContent::Classified);
    EXPECT_EQ(offCentres.geometry().sampleMm, openvdb::Vec2d(0.34));
    // Nor may the paper be seen: outside the volume is nothing, not paper.
    const Classifier paperSeen(TransferFunction({{50.0, {1, 1, 1, 0.5f}}, {300.0, {1, 1, 1, 0.1f}}}, "test"), 3,
                               1.0 / 250.0);
    EXPECT_EQ(SliceStack(section, paperSeen, openvdb::Vec3d(0, 0, 1), 1.0, 1.0).content(), StackContent::Classified);
}

/// Where lattice sample (i, j) of @a stack's front slice lies in @a volume's index space.
openvdb::Vec3d indexOfSample(const SliceStack& stack, const RenderVolume& volume, int i, int j) {
    const openvdb::Vec3d world = stack.geometry().lattice().worldFromIndex.transform(openvdb::Vec3d(i, j, 0));
    return volume.worldFromIndex().inverse().transform(world);
}

/// Whether @a x is a whole number, as a voxel centre's index is.
bool onVoxelCentre(double x) { return std::abs(x - std::round(x)) < 1e-6; }

// Across a volume's axis, a stack's samples fall on the voxel centres (and evenly
// between them), where bilinear resampling gives the trilinear field exactly; not
// when that would take them much further apart, or closer, than asked.
TEST(SliceStack, SamplesAlongAVolumesAxesFallOnItsVoxelCentres) {
    // Voxels of 1 x 1 x 1.5 mm; a stack across y has x and z in its plane.
    const GridRenderVolume volume(test::makeGrid({20, 16, 12}, hollowBallAt, openvdb::Vec3d(1.0, 1.0, 1.5)));
    struct Case {
        double askedMm, xStep, zStep;
        bool xOnCentres, zOnCentres;
    };
    // Asked coarser than the voxels, samples keep to them, but never more than twice as fine as asked (4.4).
    for (const Case c :
         {Case{0.78, 1.0, 0.78, true, false}, Case{0.7, 0.7, 0.75, false, true}, Case{1.2, 1.0, 1.5, true, true},
          Case{2.2, 1.0, 1.5, true, true}, Case{4.4, 2.0, 2.2, true, false}, Case{0.45, 0.5, 0.5, true, true}}) {
        const SliceStack stack(volume, shellClassifier(), openvdb::Vec3d(0, 1, 0), 1.0, c.askedMm);
        const StackGeometry& g = stack.geometry();
        const int xAxis = std::abs(g.e1.x()) > 0.5 ? 0 : 1;  // which of e1 and e2 runs along x
        EXPECT_DOUBLE_EQ(g.sampleMm[xAxis], c.xStep) << c.askedMm;
        EXPECT_DOUBLE_EQ(g.sampleMm[1 - xAxis], c.zStep) << c.askedMm;
        // The slices lie a voxel (1 mm) apart, a quarter of a voxel off the voxel planes.
        EXPECT_DOUBLE_EQ(g.sliceMm, 1.0);
        for (int k = 0; k < g.slices; ++k) {
            const double y = volume.worldFromIndex()
                                 .inverse()
                                 .transform(g.lattice().worldFromIndex.transform(openvdb::Vec3d(0, 0, k)))
                                 .y();
            EXPECT_NEAR(y - std::floor(y), 0.25, 1e-9) << k;
        }
        // On the voxel centres, or on them and evenly between them.
        const double xPerVoxel = std::max(1.0, 1.0 / c.xStep), zPerVoxel = std::max(1.0, 1.5 / c.zStep);
        for (int n = 0; n < std::min(g.width, g.height); ++n) {
            const openvdb::Vec3d index = indexOfSample(stack, volume, n, n);
            if (c.xOnCentres) {
                EXPECT_TRUE(onVoxelCentre(index.x() * xPerVoxel)) << c.askedMm << " " << n;
            }
            if (c.zOnCentres) {
                EXPECT_TRUE(onVoxelCentre(index.z() * zPerVoxel)) << c.askedMm << " " << n;
            }
        }
    }
    // Off the volume's axes, the spacings asked, or the least voxel edge where that is finer.
    const StackGeometry oblique = SliceStack(volume, shellClassifier(), openvdb::Vec3d(1, 2, 0.5), 1.0, 0.8).geometry();
    EXPECT_EQ(oblique.sampleMm, openvdb::Vec2d(0.8));
    EXPECT_DOUBLE_EQ(oblique.sliceMm, 1.0);
    EXPECT_EQ(SliceStack(volume, shellClassifier(), openvdb::Vec3d(1, 2, 0.5), 1.0, 1.7).geometry().sampleMm,
              openvdb::Vec2d(1.0));
}

// Each axis keeps to its own voxels: capped at the smallest voxel edge, the 4 mm
// axis would take sixteen times the samples it needs.
TEST(SliceStack, StronglyAnisotropicVoxelsAreSampledNoCoarserThanEachAxisOwn) {
    const GridRenderVolume volume(test::makeGrid({20, 16, 12}, hollowBallAt, openvdb::Vec3d(0.25, 1.0, 4.0)));
    struct Case {
        double askedMm, xStep, zStep;
    };
    // Each axis no coarser than its voxels (0.25 mm along x, 4 along z), nor over twice as fine as asked.
    for (const Case c : {Case{0.5, 0.25, 0.5}, Case{2.0, 1.0, 2.0}, Case{8.0, 4.0, 4.0}}) {
        const SliceStack stack(volume, shellClassifier(), openvdb::Vec3d(0, 1, 0), 1.0, c.askedMm);
        const StackGeometry& g = stack.geometry();
        const int xAxis = std::abs(g.e1.x()) > 0.5 ? 0 : 1;
        EXPECT_DOUBLE_EQ(g.sampleMm[xAxis], c.xStep) << c.askedMm;
        EXPECT_DOUBLE_EQ(g.sampleMm[1 - xAxis], c.zStep) << c.askedMm;
        EXPECT_TRUE(g.samplesOnVoxels) << c.askedMm;
    }
}

// Slices once lay a shortest voxel edge apart along every normal: 12^3 voxels of
// 1e-6 x 1 x 1 mm stacked along a 1 mm edge took 12 million of them.
TEST(SliceStack, VeryUnequalVoxelsTakeNoMoreSlicesThanRaysCanCross) {
    const int mostSlices = 32 * (12 + 12 + 12) + 2;
    for (const openvdb::Vec3d spacing : {openvdb::Vec3d(1e-6, 1.0, 1.0), openvdb::Vec3d(1e6, 1.0, 1.0)}) {
        const GridRenderVolume volume(test::makeGrid({12, 12, 12}, hollowBallAt, spacing));
        for (const openvdb::Vec3d normal :
             {openvdb::Vec3d(1, 0, 0), openvdb::Vec3d(0, 1, 0), openvdb::Vec3d(1, 1, 1)}) {
            const OrthoCamera camera =
                makeCamera({30, 20}, worldCorners(volume.worldFromIndex(), volume.box()), 64, 64);
            const SliceStack stack(volume, shellClassifier(), normal, 1.0,
                                   ShearWarpSettings{}.sampleMmFor(camera, volume));
            EXPECT_LE(stack.geometry().slices, mostSlices) << spacing << " along " << normal;
        }
    }
    // Equal voxels keep the spacing asked, down to the finest a user may ask, along a diagonal too.
    const SliceStack fine(hollowBall(), shellClassifier(), openvdb::Vec3d(1, 1, 1), 0.05, 1.0);
    EXPECT_DOUBLE_EQ(fine.geometry().sliceVoxels, 0.05);
    EXPECT_DOUBLE_EQ(fine.geometry().sliceMm, 0.05);
}

// A coarse first image must come quickly: a preview keeps to the spacing asked.
TEST(SliceStack, APreviewTakesTheSpacingAskedHoweverCoarse) {
    const GridRenderVolume volume(test::makeGrid({20, 16, 12}, hollowBallAt, openvdb::Vec3d(1.0, 1.0, 1.5)));
    const SliceStack preview(volume, shellClassifier(), openvdb::Vec3d(0, 1, 0), 1.0, 2.2, {}, nullptr,
                             StackSampling::Preview);
    const StackGeometry& g = preview.geometry();
    const int xAxis = std::abs(g.e1.x()) > 0.5 ? 0 : 1;
    EXPECT_DOUBLE_EQ(g.sampleMm[xAxis], 2.0);  // two voxels, on their centres
    EXPECT_DOUBLE_EQ(g.sampleMm[1 - xAxis], 2.2);
}

// Classified samples blend colours classified at the samples, not the colour of
// blended voxels: on the voxel centres they would gain nothing and scored far lower
// on a colour section. Their stacks take the spacing asked.
TEST(SliceStack, ClassifiedSamplesTakeTheSpacingAskedAlongTheAxesToo) {
    const GridRenderVolume volume(test::makeGrid({20, 16, 12}, hollowBallAt, openvdb::Vec3d(1.0, 1.0, 1.5)));
    const SliceStack layered({{&volume, shellClassifier()}, {&volume, shellClassifier()}}, openvdb::Vec3d(0, 1, 0), 1.0,
                             0.78);
    ASSERT_EQ(layered.valueLevels(), nullptr);
    EXPECT_EQ(layered.geometry().sampleMm, openvdb::Vec2d(0.78));
    EXPECT_FALSE(onVoxelCentre(indexOfSample(layered, volume, 3, 3).x()) &&
                 onVoxelCentre(indexOfSample(layered, volume, 4, 4).x()));
    // The slices still lie a quarter of a voxel off the voxel planes.
    const double y = volume.worldFromIndex().inverse().transform(layered.geometry().origin).y();
    EXPECT_NEAR(y - std::floor(y), 0.25, 1e-9);
}

// Resampling a slice between its outermost samples and the space beyond must meet
// the background's value: the lattice reaches one sample beyond the volume's cells
// on every side, whether its samples fall on the voxel centres or not.
TEST(SliceStack, TheLatticeReachesOneSampleBeyondTheVolumeOnEverySide) {
    const GridRenderVolume volume(test::makeGrid({20, 16, 12}, hollowBallAt, openvdb::Vec3d(1.0, 1.0, 1.5)));
    const openvdb::Vec3d lo(-0.5), hi(19.5, 15.5, 11.5);  // the cells, in index space
    const auto inside = [&](const openvdb::Vec3d& p, int axis) { return p[axis] >= lo[axis] && p[axis] <= hi[axis]; };
    for (const openvdb::Vec3d& direction : {openvdb::Vec3d(0, 1, 0), openvdb::Vec3d(0, 0, 1)}) {
        for (const double askedMm : {0.8, 1.0, 1.3}) {
            const SliceStack stack(volume, shellClassifier(), direction, 1.0, askedMm);
            const StackGeometry& g = stack.geometry();
            const int mid1 = g.width / 2, mid2 = g.height / 2;
            for (int axis = 0; axis < 3; ++axis) {
                if (std::abs(direction[axis]) > 0.5) continue;  // across the slices, not in their plane
                const bool alongE1 = std::abs(std::abs(g.e1[axis]) - 1.0) < 1e-9;
                const int last = (alongE1 ? g.width : g.height) - 1;
                const auto sample = [&](int n) {
                    return alongE1 ? indexOfSample(stack, volume, n, mid2) : indexOfSample(stack, volume, mid1, n);
                };
                EXPECT_FALSE(inside(sample(0), axis)) << askedMm << " axis " << axis;
                EXPECT_TRUE(inside(sample(1), axis)) << askedMm << " axis " << axis;
                EXPECT_TRUE(inside(sample(last - 1), axis)) << askedMm << " axis " << axis;
                EXPECT_FALSE(inside(sample(last), axis)) << askedMm << " axis " << axis;
            }
        }
    }
}

// A viewer cancels a build the view has moved away from: the build stops at the
// next slab of eight slices, however far it got, and says so.
TEST(SliceStack, ABuildStopsAtTheNextSlabOnceCancelled) {
    const GridRenderVolume ball = hollowBall();
    std::atomic<bool> cancel{true};
    EXPECT_THROW(SliceStack(ball, shellClassifier(), openvdb::Vec3d(0, 0, 1), 1.0, 1.0, {}, &cancel), Cancelled);
    // Set after the first slab (of five): no more are built.
    cancel = false;
    int slabs = 0;
    const ProgressFn cancelAfterOne = [&](double) {
        ++slabs;
        cancel = true;
    };
    EXPECT_THROW(SliceStack(ball, shellClassifier(), openvdb::Vec3d(0, 0, 1), 1.0, 1.0, cancelAfterOne, &cancel),
                 Cancelled);
    EXPECT_EQ(slabs, 1);
    // Never set, the build finishes.
    cancel = false;
    EXPECT_EQ(SliceStack(ball, shellClassifier(), openvdb::Vec3d(0, 0, 1), 1.0, 1.0, {}, &cancel).slices().size(), 40u);
}

/// Checks that every cell of @a stack (across z over hollowBall(), one voxel a
/// sample) that can be seen keeps its four corners, with their true values in
/// codes: what compositing resamples. @return the cells that can be seen
std::size_t checkVisibleCellsAreKept(const SliceStack& stack) {
    // Lattice sample (i, j) of slice k is at voxel (i - 1, j - 1, z_k): the lattice
    // reaches a sample of background beyond the volume on each side, and its slices
    // lie a quarter of a voxel off the voxel planes.
    constexpr int kSide = 42;
    const Lattice lattice = stack.geometry().lattice();
    EXPECT_EQ(stack.geometry().width, kSide);
    EXPECT_EQ(stack.geometry().height, kSide);
    EXPECT_EQ(stack.geometry().slices, 40);
    const ValueLevels& levels = *stack.valueLevels();
    std::size_t visibleCells = 0;
    for (int k = 0; k < 40; ++k) {
        const Slice& slice = stack.slices()[k];
        // The ball's grid has the world's axes and origin: index space is world space.
        const double z = lattice.worldFromIndex.transform(openvdb::Vec3d(0, 0, k)).z();
        const int below = int(std::floor(z));
        const auto valueAt = [&](int i, int j, int plane) {
            return plane < 0 || plane >= 40 ? 0.0 : hollowBallAt(i, j, plane);
        };
        const auto codeAt = [&](int i, int j) {
            if (i < 1 || j < 1 || i > 40 || j > 40) return int(slice.coding.code(0.0f));
            const double t = z - below;
            return int(slice.coding.code(
                float((1 - t) * valueAt(i - 1, j - 1, below) + t * valueAt(i - 1, j - 1, below + 1))));
        };
        // Each row's stored codes by column, -1 where the row keeps none.
        std::vector<int> stored(kSide * kSide, -1);
        for (int j = 0; j < kSide; ++j) {
            for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r) {
                const RowRun& run = slice.runs[r];
                // The neighbours on either side are the row's own, or the background beyond it.
                EXPECT_NEAR(slice.codes[run.offset - 1], codeAt(int(run.begin) - 1, j), 1);
                EXPECT_NEAR(slice.codes[run.offset + run.end - run.begin], codeAt(int(run.end), j), 1);
                for (std::uint32_t i = run.begin; i < run.end; ++i)
                    stored[j * kSide + i] = slice.codes[run.offset + i - run.begin];
            }
        }
        for (int j = 0; j + 1 < kSide; ++j) {
            for (int i = 0; i + 1 < kSide; ++i) {
                const int corners[4] = {codeAt(i, j), codeAt(i + 1, j), codeAt(i, j + 1), codeAt(i + 1, j + 1)};
                const auto levelOf = [&](int code) { return ValueLevels::nearest(slice.coding.level(float(code))); };
                const int lo = levelOf(*std::min_element(corners, corners + 4)),
                          hi = levelOf(*std::max_element(corners, corners + 4));
                if (!levels.anyVisibleLevel(lo, hi)) continue;
                ++visibleCells;
                // Within a code: the stack interpolates in floats, this check in doubles.
                EXPECT_NEAR(stored[j * kSide + i], corners[0], 1) << i << " " << j << " " << k;
                EXPECT_NEAR(stored[j * kSide + i + 1], corners[1], 1) << i << " " << j << " " << k;
                EXPECT_NEAR(stored[(j + 1) * kSide + i], corners[2], 1) << i << " " << j << " " << k;
                EXPECT_NEAR(stored[(j + 1) * kSide + i + 1], corners[3], 1) << i << " " << j << " " << k;
            }
        }
    }
    return visibleCells;
}

TEST(SliceStack, RowsOfValuesKeepEveryCellThatCanBeSeenWithItsNeighbours) {
    const GridRenderVolume ball = hollowBall();
    // Across z at one voxel a sample, on the voxel centres across the slices.
    EXPECT_GT(checkVisibleCellsAreKept(SliceStack(ball, shellClassifier(), openvdb::Vec3d(0, 0, 1), 1.0, 1.0)), 1000u);
    // Only a band of values can be seen: a cell whose corners lie below and above it
    // holds values that can, though none of its corners can.
    const Classifier band(
        TransferFunction(
            {{400.0, {1, 1, 1, 0}}, {401.0, {1, 1, 1, 0.5f}}, {420.0, {1, 1, 1, 0.5f}}, {421.0, {1, 1, 1, 0}}}, "test"),
        1);
    EXPECT_GT(checkVisibleCellsAreKept(SliceStack(ball, band, openvdb::Vec3d(0, 0, 1), 1.0, 1.0)), 1000u);
}

/// The slices of @a stack that keep a sample two or more from the lattice's edges
/// (nearer, the cells that reach the background beyond the volume cross every value
/// between the volume's and the background's, as the ray marcher sees them).
std::vector<int> slicesWithRuns(const SliceStack& stack) {
    const StackGeometry& g = stack.geometry();
    std::vector<int> kept;
    for (int k = 0; k < g.slices; ++k) {
        const Slice& slice = stack.slices()[k];
        bool keeps = false;
        for (int j = 2; j + 2 < g.height; ++j) {
            for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r) {
                keeps = keeps || (int(slice.runs[r].end) > 2 && int(slice.runs[r].begin) < g.width - 2);
            }
        }
        if (keeps) kept.push_back(k);
    }
    return kept;
}

TEST(SliceStack, SegmentsKeepTheSlicesOnEitherSideOfABandThatFallsBetweenThem) {
    // Values rise 100 a voxel along z; two bands fall between slices: 3 and 4, inside
    // a slab of eight, and 7 and 8, across two slabs (the first slab's last slice
    // waits for the second's first).
    const GridRenderVolume ramp(test::makeGrid(
        {12, 12, 24}, [](int, int, int k) { return 100.0f * k; }, openvdb::Vec3d(1.0), -1.0));
    const std::array<float, 4> clear{1, 1, 1, 0}, seen{1, 1, 1, 0.5f};
    const Classifier bands(TransferFunction({{329.0, clear},
                                             {330.0, seen},
                                             {360.0, seen},
                                             {361.0, clear},
                                             {729.0, clear},
                                             {730.0, seen},
                                             {760.0, seen},
                                             {761.0, clear}},
                                            "test"),
                           1);
    const openvdb::Vec3d up(0, 0, 1);
    SegmentViews segments{Classification::Segments, 0.0};
    const SliceStack stack(ramp, bands, up, 1.0, 1.0, {}, nullptr, StackSampling::Voxels, segments);
    ASSERT_EQ(stack.geometry().slices, 24);
    EXPECT_EQ(stack.classification(), Classification::Segments);
    EXPECT_EQ(slicesWithRuns(stack), (std::vector<int>{3, 4, 7, 8}));
    // Each sample alone is invisible, and so are the cells of each slice.
    EXPECT_TRUE(slicesWithRuns(SliceStack(ramp, bands, up, 1.0, 1.0)).empty());
    // A view off the normal reaches further across from one slice to the next: the
    // slices keep a margin around the samples they would keep for a view along it.
    const GridRenderVolume step(test::makeGrid(
        {24, 24, 24}, [](int i, int, int k) { return i < 12 ? 0.0f : 100.0f * k; }, openvdb::Vec3d(1.0), -1.0));
    const auto keptInRow = [](const SliceStack& s, int k, int j) {
        const Slice& slice = s.slices()[k];
        std::uint32_t count = 0;
        for (std::uint32_t r = slice.rowRuns[j]; r < slice.rowRuns[j + 1]; ++r)
            count += slice.runs[r].end - slice.runs[r].begin;
        return count;
    };
    segments.maxAngleDeg = 45.0;  // one sample across a slice spacing
    const SliceStack along(step, bands, up, 1.0, 1.0, {}, nullptr, StackSampling::Voxels,
                           {Classification::Segments, 0.0});
    const SliceStack oblique(step, bands, up, 1.0, 1.0, {}, nullptr, StackSampling::Voxels, segments);
    EXPECT_EQ(keptInRow(oblique, 7, 12), keptInRow(along, 7, 12) + 1);
}

TEST(SliceStack, RowsKeepOnlyTheirRunsOfVisibleSamples) {
    const GridRenderVolume ball = hollowBall();
    // Two layers keep classified samples (a grey volume alone would keep values).
    const SliceStack stack({{&ball, shellClassifier()}, {&ball, shellClassifier()}}, openvdb::Vec3d(0.3, 0.2, 1.0), 1.0,
                           1.0);
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
                if (r > first) {
                    EXPECT_GE(run.begin - slice.runs[r - 1].end, std::uint32_t(kRunGap));
                }
                // Each run lies between two transparent samples.
                EXPECT_EQ(slice.samples[run.offset - 1].a, 0);
                EXPECT_EQ(slice.samples[run.offset + run.end - run.begin].a, 0);
                if (r + 1 < end) {
                    EXPECT_EQ(slice.runs[r + 1].offset, run.offset + run.end - run.begin + 2);
                }
            }
        }
    }
    EXPECT_GT(runs, 0u);
    // Rows through the middle of the ball cross the shell twice.
    EXPECT_GT(rowsWithAHollow, 100u);
}

}  // namespace
}  // namespace gvr
