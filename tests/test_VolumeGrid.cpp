// Volume grids: float and vec3s are the one list, and the fit, the renderer and the
// baselines refuse any other grid with the one message that names it.

#include "pipeline/Error.h"
#include "pipeline/VolumeGrid.h"
#include "pipeline/VolumeTarget.h"
#include "render/RenderVolume.h"
#include "tests/TestHelpers.h"
#include "workflow/BaselineCodecs.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(VolumeGrid, FloatAndVec3sGridsAreVolumeGridsAndNoOthers) {
    EXPECT_TRUE(isVolumeGrid(*openvdb::FloatGrid::create()));
    EXPECT_TRUE(isVolumeGrid(*openvdb::Vec3SGrid::create()));
    EXPECT_FALSE(isVolumeGrid(*openvdb::DoubleGrid::create()));
    EXPECT_FALSE(isVolumeGrid(*openvdb::Int32Grid::create()));
}

TEST(VolumeGrid, FitRenderAndBaselineRefuseOtherGridsNamingThem) {
    openvdb::DoubleGrid::Ptr grid = openvdb::DoubleGrid::create();
    grid->setName("density");
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 5.0);
    const std::string expected = "grid 'density' holds double; gvr works on float (grey) and vec3s (RGB) grids";
    const std::string fit = test::errorMessageOf<InputError>([&] { VolumeTarget(grid, "scan.vdb"); });
    EXPECT_NE(fit.find("scan.vdb: " + expected), std::string::npos) << fit;
    const std::string render = test::errorMessageOf<InputError>([&] { GridRenderVolume volume(grid); });
    EXPECT_NE(render.find(expected), std::string::npos) << render;
    test::TempDir dir;
    BaselineSettings settings;
    settings.method = BaselineMethod::VdbHalf;
    const std::string baseline =
        test::errorMessageOf<InputError>([&] { runBaseline(*grid, settings, dir.path("stream.vdb"), {}); });
    EXPECT_NE(baseline.find(expected), std::string::npos) << baseline;
}

}  // namespace
}  // namespace gvr
