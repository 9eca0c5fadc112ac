// Sampling the Gaussian field into a sparse grid: exact against point evaluation,
// sparse where nothing reaches, seamless across leaves at any resolution.

#include "pipeline/Error.h"
#include "pipeline/FieldToGrid.h"
#include "pipeline/FloatVolume.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gvr {
namespace {

using openvdb::Coord;
using openvdb::math::Mat4d;

Mat4d anisotropicShear() {
    Mat4d m = Mat4d::identity();
    m.setToScale(openvdb::Vec3d(0.7, 0.7, 2.5));
    m(1, 2) = 0.3;  // j leans into z, like a gantry tilt
    m.setTranslation(openvdb::Vec3d(-40.0, 12.0, 7.0));
    return m;
}

TEST(FieldToGrid, SourceLatticeHoldsExactlyThePointEvaluation) {
    const GaussianField field(test::randomGaussians(150, 1, 30.0f, 1), 3.0f);
    const Mat4d worldFromIndex = anisotropicShear();
    const Lattice lattice = sourceLattice(worldFromIndex, openvdb::Vec3i(34, 30, 28));
    FieldToGridSettings settings;
    settings.mapping.offset = {-1000.0, 0.0, 0.0};  // HU-like: normalised 0 is -1000
    settings.mapping.scale = 2000.0;
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(fieldToGrid(field, worldFromIndex, lattice, settings));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "density");
    EXPECT_EQ(grid->background(), -1000.0f);
    EXPECT_TRUE(grid->transform().baseMap()->getAffineMap()->getMat4().eq(worldFromIndex));
    std::vector<std::uint32_t> hits;
    std::size_t reached = 0;
    for (auto ijk = lattice.box.begin(); ijk; ++ijk) {
        const float x[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        float value;
        field.evaluate(x, &value, hits);
        if (value == 0.0f) {
            ASSERT_FALSE(grid->tree().isValueOn(*ijk)) << *ijk;
            ASSERT_EQ(grid->tree().getValue(*ijk), -1000.0f);
            continue;
        }
        ++reached;
        ASSERT_TRUE(grid->tree().isValueOn(*ijk)) << *ijk;
        ASSERT_EQ(grid->tree().getValue(*ijk), float(-1000.0 + 2000.0 * value)) << *ijk;
    }
    EXPECT_GT(reached, 1000u);
    EXPECT_LT(reached, lattice.box.volume());  // sparse: part of the box is out of reach
}

TEST(FieldToGrid, ThresholdKeepsLowVoxelsInactive) {
    const GaussianField field(test::randomGaussians(80, 1, 20.0f, 2), 3.0f);
    const Lattice lattice = sourceLattice(Mat4d::identity(), openvdb::Vec3i(24, 24, 24));
    FieldToGridSettings settings;
    settings.threshold = 0.3;
    const auto grid =
        openvdb::gridPtrCast<openvdb::FloatGrid>(fieldToGrid(field, Mat4d::identity(), lattice, settings));
    std::vector<std::uint32_t> hits;
    for (auto ijk = lattice.box.begin(); ijk; ++ijk) {
        const float x[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        float value;
        field.evaluate(x, &value, hits);
        ASSERT_EQ(grid->tree().isValueOn(*ijk), value > 0.3f) << *ijk;
    }
}

TEST(FieldToGrid, RgbBecomesAColourGrid) {
    const GaussianField field(test::randomGaussians(60, 3, 16.0f, 3), 3.0f);
    const Lattice lattice = sourceLattice(Mat4d::identity(), openvdb::Vec3i(16, 16, 16));
    FieldToGridSettings settings;
    settings.mapping.offset = {10.0, 20.0, 30.0};
    settings.mapping.scale = 200.0;
    const auto grid =
        openvdb::gridPtrCast<openvdb::Vec3SGrid>(fieldToGrid(field, Mat4d::identity(), lattice, settings));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "color");
    EXPECT_EQ(grid->background(), openvdb::Vec3s(10.0f, 20.0f, 30.0f));
    std::vector<std::uint32_t> hits;
    const float x[3] = {8.0f, 8.0f, 8.0f};
    float value[3];
    field.evaluate(x, value, hits);
    const openvdb::Vec3s stored = grid->tree().getValue(Coord(8, 8, 8));
    for (int c = 0; c < 3; ++c) EXPECT_EQ(stored[c], float(settings.mapping.offset[c] + 200.0 * value[c]));
}

TEST(FieldToGrid, ResizedLatticeCoversTheSourceExtent) {
    const Mat4d worldFromIndex = anisotropicShear();
    const openvdb::Vec3i dims(34, 30, 28);
    const Lattice fine = resizedLattice(worldFromIndex, dims, 0.35);
    // The j axis is sqrt(0.7^2 + 0.3^2) mm long because of the shear.
    const double steps[3] = {0.35 / 0.7, 0.35 / std::sqrt(0.58), 0.35 / 2.5};
    EXPECT_EQ(fine.box.dim(), Coord(68, 66, 200));  // ceil(34 / 0.5), ceil(30 / 0.4596), 28 / 0.14
    // The first fine voxel sits half a fine voxel in from the source's corner.
    const openvdb::Vec3d corner = worldFromIndex.transform(openvdb::Vec3d(-0.5, -0.5, -0.5));
    const openvdb::Vec3d first = fine.worldFromIndex.transform(openvdb::Vec3d(0.0));
    const openvdb::Vec3d expected =
        corner + worldFromIndex.transform3x3(openvdb::Vec3d(steps[0] / 2, steps[1] / 2, steps[2] / 2));
    EXPECT_TRUE(first.eq(expected, 1e-9)) << first << " vs " << expected;
    EXPECT_NEAR(voxelSizeForResolution(worldFromIndex, dims, 100), 28 * 2.5 / 100, 1e-12);
    EXPECT_THROW(resizedLattice(worldFromIndex, dims, 0.0), std::exception);
    EXPECT_THROW(resizedLattice(worldFromIndex, dims, 1e-6), std::exception);  // absurd size
    // 1e300 mm made a transform whose determinant overflowed: a file no reader takes.
    EXPECT_EQ(resizedLattice(worldFromIndex, dims, 28 * 2.5).box.dim(), Coord(1, 1, 1));
    EXPECT_EQ(test::errorMessageOf<InputError>([&] { resizedLattice(worldFromIndex, dims, 1e300); }),
              "`voxel_size`: 1e+300 mm is larger than the volume's longest extent, 70 mm");
}

/// Central second difference along x at a voxel, or NaN where a neighbour is missing.
float secondDifference(const openvdb::FloatGrid& grid, const Coord& ijk) {
    const auto& tree = grid.tree();
    return tree.getValue(ijk.offsetBy(-1, 0, 0)) - 2.0f * tree.getValue(ijk) + tree.getValue(ijk.offsetBy(1, 0, 0));
}

TEST(FieldToGrid, TwiceTheResolutionIsSeamlessAcrossLeaves) {
    // Broad, overlapping Gaussians: a smooth field whose every sample has many contributors.
    GaussianParameters params = test::randomGaussians(60, 1, 24.0f, 4);
    for (std::size_t g = 0; g < params.count(); ++g) {
        for (int a = 0; a < 3; ++a) params.at(kLogScales, g)[a] = 1.2f;
    }
    const GaussianField field(params, 3.0f);
    const Lattice fine = resizedLattice(Mat4d::identity(), openvdb::Vec3i(24, 24, 24), 0.5);
    const auto grid =
        openvdb::gridPtrCast<openvdb::FloatGrid>(fieldToGrid(field, Mat4d::identity(), fine, FieldToGridSettings{}));
    const Mat4d fieldFromFine = fine.worldFromIndex;
    std::vector<std::uint32_t> hits;
    float worstBorder = 0.0f, worstInside = 0.0f;
    for (auto ijk = fine.box.begin(); ijk; ++ijk) {
        const openvdb::Vec3d p = fieldFromFine.transform((*ijk).asVec3d());
        const float x[3] = {float(p[0]), float(p[1]), float(p[2])};
        float expected;
        field.evaluate(x, &expected, hits);
        ASSERT_EQ(grid->tree().getValue(*ijk), expected) << *ijk;
        if ((*ijk).x() == 0 || (*ijk).x() + 1 == fine.box.dim().x()) continue;
        const float curvature = std::abs(secondDifference(*grid, *ijk));
        const int inLeaf = (*ijk).x() & 7;
        if (inLeaf == 0 || inLeaf == 7)
            worstBorder = std::max(worstBorder, curvature);
        else
            worstInside = std::max(worstInside, curvature);
    }
    EXPECT_GT(worstInside, 0.0f);
    EXPECT_LE(worstBorder, worstInside * 1.01f) << "a seam: leaf borders bend more than leaf interiors";
}

TEST(FieldToGrid, NothingOutsideTheFieldsOwnVoxels) {
    const GaussianField field(test::randomGaussians(100, 1, 20.0f, 6), 3.0f);
    FieldToGridSettings settings;
    settings.fieldBox = openvdb::CoordBBox(Coord(0), Coord(9, 19, 19));  // the source stopped at i = 9
    const Lattice wide = sourceLattice(Mat4d::identity(), openvdb::Vec3i(20, 20, 20));
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(fieldToGrid(field, Mat4d::identity(), wide, settings));
    std::vector<std::uint32_t> hits;
    std::size_t inside = 0;
    for (auto ijk = wide.box.begin(); ijk; ++ijk) {
        if ((*ijk).x() > 9) {
            ASSERT_FALSE(grid->tree().isValueOn(*ijk)) << *ijk;
            continue;
        }
        const float x[3] = {float((*ijk).x()), float((*ijk).y()), float((*ijk).z())};
        float value;
        field.evaluate(x, &value, hits);
        ASSERT_EQ(grid->tree().getValue(*ijk), value) << *ijk;
        inside += grid->tree().isValueOn(*ijk);
    }
    EXPECT_GT(inside, 100u);
}

TEST(FieldToGrid, NoGaussiansGiveAnEmptyGrid) {
    const GaussianField field(GaussianParameters(0, 1), 3.0f);
    const auto grid = fieldToGrid(field, Mat4d::identity(), sourceLattice(Mat4d::identity(), openvdb::Vec3i(9, 9, 9)),
                                  FieldToGridSettings{});
    EXPECT_EQ(grid->activeVoxelCount(), 0u);
}

}  // namespace
}  // namespace gvr
