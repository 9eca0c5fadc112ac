// The fit's view of a volume: values, blocks and gradients read alike.

#include "pipeline/Error.h"
#include "pipeline/LatticeSampler.h"
#include "pipeline/VolumeTarget.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace gvr {
namespace {

float waves(int i, int j, int k) { return 100.0f + 80.0f * std::sin(0.4f * i) * std::cos(0.3f * j) + 5.0f * k; }

TEST(VolumeTarget, BlockGradientsAreThePointGradientsIncludingAtFacesAndEdges) {
    // 19 x 13 x 10 voxels: blocks reach past the box, and faces need neighbours from other blocks.
    const VolumeTarget target(test::makeGrid({19, 13, 10}, waves, openvdb::Vec3d(1.0), 120.0), "waves");
    std::size_t checked = 0;
    for (const openvdb::Coord& origin : blockOrigins(target.box())) {
        float gradients[kBlockVoxels];
        target.blockGradientMagnitudes(origin, gradients);
        for (int offset = 0; offset < kBlockVoxels; ++offset) {
            const openvdb::Coord ijk = origin.offsetBy(offset >> 6, (offset >> 3) & 7, offset & 7);
            ASSERT_EQ(gradients[offset], target.gradientMagnitude(ijk)) << ijk;
            ++checked;
        }
    }
    EXPECT_EQ(checked, 3u * 2u * 2u * 512u);
}

TEST(VolumeTarget, ValuesSpanningMoreThanFloatHoldsAreRefused) {
    // A float32 NIfTI holding +-3.4028234e38 was fitted, and its asset's value
    // mapping, 6.8e38 wide, was then refused by every reader.
    const openvdb::GridBase::Ptr extremes = test::makeGrid(
        {8, 8, 8}, [](int i, int, int) { return i < 4 ? -FLT_MAX : FLT_MAX; }, openvdb::Vec3d(1.0), -FLT_MAX);
    const std::string message = test::errorMessageOf<InputError>([&] { VolumeTarget(extremes, "limits.nii"); });
    EXPECT_NE(message.find("limits.nii: values span "), std::string::npos) << message;
    EXPECT_NE(message.find("wider than float32 can hold"), std::string::npos) << message;
    const openvdb::GridBase::Ptr half =
        test::makeGrid({8, 8, 8}, [](int i, int, int) { return i < 4 ? 0.0f : FLT_MAX; });
    EXPECT_NO_THROW(VolumeTarget(half, "half.nii"));
}

TEST(VolumeTarget, VoxelsBeyondFloatExactIndicesAreRefusedNamingTheFix) {
    // Near index 2^31 the fit once ended in an Embree assertion with no message.
    for (const openvdb::Coord far : {openvdb::Coord(2147483000, 0, 0), openvdb::Coord(0, -20000000, 5)}) {
        auto grid = openvdb::FloatGrid::create(0.0f);
        grid->setName("density");
        grid->tree().setValueOn(far, 1.0f);
        grid->tree().setValueOn(far + openvdb::Coord(0, 1, 0), 1.0f);
        try {
            VolumeTarget target(grid, "far.vdb");
            ADD_FAILURE() << "voxels at " << far << " were accepted";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find("beyond +-2^24"), std::string::npos) << error.what();
            EXPECT_NE(std::string(error.what()).find("ingest it again"), std::string::npos) << error.what();
        }
    }
    auto near = openvdb::FloatGrid::create(0.0f);
    near->denseFill(openvdb::CoordBBox(openvdb::Coord(16000000), openvdb::Coord(16000007)), 1.0f, true);
    EXPECT_NO_THROW(VolumeTarget(near, "near.vdb"));
}

}  // namespace
}  // namespace gvr
