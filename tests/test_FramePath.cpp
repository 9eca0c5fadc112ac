// How render --orbit names its frames.

#include "workflow/FramePath.h"

#include <gtest/gtest.h>

namespace gvr {
namespace {

TEST(FramePath, OrbitFramesAreNumberedBesideTheOutputAndASingleFrameKeepsItsName) {
    EXPECT_EQ(framePath("out/view.png", 0, 1), "out/view.png");
    EXPECT_EQ(framePath("out/view.png", 7, 120), "out/view_0007.png");
    EXPECT_EQ(framePath("view.exr", 12345, 20000), "view_12345.exr");
    EXPECT_EQ(framePath("a.b/frame.png", 3, 6), "a.b/frame_0003.png") << "a dot in a folder is no extension";
}

}  // namespace
}  // namespace gvr
