#include "io/formats/NiftiImage.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace gvr {
namespace {

// Under LeakSanitizer (.ci/sanitize.sh) an image the pointer failed to free, with
// its 64 KiB of voxels, is reported as a leak and fails this test.
TEST(NiftiImage, ThePointerFreesTheImageAndItsVoxels) {
    const std::int64_t dims[8] = {3, 32, 32, 16, 1, 1, 1, 1};
    NiftiImagePtr image(nifti_make_new_nim(dims, NIFTI_TYPE_INT16, /*alloc_data=*/1));
    ASSERT_TRUE(image);
    ASSERT_NE(image->data, nullptr);
    EXPECT_EQ(image->nvox, 32 * 32 * 16);
    image.reset();
    EXPECT_FALSE(image);
}

}  // namespace
}  // namespace gvr
