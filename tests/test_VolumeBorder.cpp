// The border median looks at the six faces only, whatever the inside holds.

#include "pipeline/VolumeBorder.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

namespace gvr {
namespace {

bool onFace(const openvdb::CoordBBox& box, const openvdb::Coord& ijk) {
    for (int a = 0; a < 3; ++a) {
        if (ijk[a] == box.min()[a] || ijk[a] == box.max()[a]) return true;
    }
    return false;
}

TEST(VolumeBorder, SeesOnlyTheFaces) {
    const openvdb::CoordBBox box(openvdb::Coord(0, 0, 0), openvdb::Coord(9, 7, 5));
    int outside = 0;
    const double median = borderMedian(box, [&](const openvdb::Coord& ijk) {
        if (!onFace(box, ijk)) ++outside;
        return onFace(box, ijk) ? 240.0 : -1000.0;
    });
    EXPECT_EQ(median, 240.0);
    EXPECT_EQ(outside, 0);
}

TEST(VolumeBorder, MedianBeatsAMinorityOfOutliers) {
    // One face of 12 x 12 out of six bright: the median stays with the other five.
    const openvdb::CoordBBox box(openvdb::Coord(-3, 4, 10), openvdb::Coord(8, 15, 21));
    const double median =
        borderMedian(box, [&](const openvdb::Coord& ijk) { return ijk.x() == box.min().x() ? 1e9 : 5.0; });
    EXPECT_EQ(median, 5.0);
}

TEST(VolumeBorder, SingleVoxelBox) {
    const openvdb::CoordBBox box(openvdb::Coord(2, 2, 2), openvdb::Coord(2, 2, 2));
    EXPECT_EQ(borderMedian(box, [](const openvdb::Coord&) { return -7.5; }), -7.5);
}

TEST(VolumeBorder, LargeFacesAreSubsampled) {
    // 640 voxels a side: every 10th row and column, not all 409,600 per face.
    const openvdb::CoordBBox box(openvdb::Coord(0), openvdb::Coord(639));
    std::size_t calls = 0;
    borderMedian(box, [&](const openvdb::Coord&) {
        ++calls;
        return 0.0;
    });
    EXPECT_EQ(calls, std::size_t(6 * 64 * 64));
}

}  // namespace
}  // namespace gvr
