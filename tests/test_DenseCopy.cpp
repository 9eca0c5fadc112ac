#include "io/DenseCopy.h"
#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(DenseCopy, CopiesTheBoxAsSampleGridDoes) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    grid->tree().setValue(openvdb::Coord(1, 0, 2), 5.0f);
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(2, 1, 3));
    const FloatVolume copy = denseCopy(*grid, box, "g.vdb", "compare");
    EXPECT_EQ(copy.values, sampleGrid(*grid, box).values);
    EXPECT_EQ(copy.at(1, 0, 2)[0], 5.0f);
}

TEST(DenseCopy, ABoxBeyondTheMemoryIsRefusedBeforeAnyAllocation) {
    // In range for OpenVDB's coordinates (2^30 a side), yet 2^60 voxels: what a
    // file's gvr_dims metadata may claim.
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    VolumeMetadata metadata;
    metadata.sourceType = "uint8";
    metadata.dims = openvdb::Vec3i(1 << 30, 1 << 30, 1);
    writeVolumeMetadata(metadata, *grid);
    const std::string message =
        test::errorMessageOf<InputError>([&] { denseCopy(*grid, volumeBox(*grid), "big.vdb", "compare"); });
    EXPECT_EQ(message.rfind("big.vdb: a volume of 1073741824x1073741824x1 voxels needs ", 0), 0u) << message;
    EXPECT_NE(message.find(" to compare, but only "), std::string::npos) << message;
}

}  // namespace
}  // namespace gvr
