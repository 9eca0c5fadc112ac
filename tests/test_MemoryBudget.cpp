// The memory budget: dimensions out of OpenVDB's range and volumes that cannot fit
// are refused by name before anything is allocated. A ceiling stands in for a small
// machine, so the sizes in the messages can be checked by hand.

#include "io/guard/MemoryBudget.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace gvr {
namespace {

/// Lifts the ceiling again even when an assertion fails, so later tests see the machine.
class Ceiling {
public:
    explicit Ceiling(std::uint64_t bytes) { setMemoryCeiling(bytes); }
    ~Ceiling() { setMemoryCeiling(0); }
};

constexpr std::int64_t kLargest = std::int64_t(1) << 30;

TEST(MemoryBudget, EachDimensionMustLieBetweenOneAndTwoToThe30th) {
    EXPECT_NO_THROW(checkDimensions("v.raw", {1, 1, 1}));
    EXPECT_NO_THROW(checkDimensions("v.raw", {kLargest, 1, kLargest}));
    EXPECT_EQ(test::errorMessageOf<InputError>([] {
                  checkDimensions("v.raw", {0, 2, 3});
              }),
              "v.raw: dimensions 0x2x3 are out of range (each must be 1..1073741824)");
    EXPECT_EQ(test::errorMessageOf<InputError>([] {
                  checkDimensions("v.raw", {4, -5, 6});
              }),
              "v.raw: dimensions 4x-5x6 are out of range (each must be 1..1073741824)");
    EXPECT_EQ(test::errorMessageOf<InputError>([] {
                  checkDimensions("v.raw", {1, 1, kLargest + 1});
              }),
              "v.raw: dimensions 1x1x1073741825 are out of range (each must be 1..1073741824)");
    const std::int64_t most = std::numeric_limits<std::int64_t>::max();
    EXPECT_NE(test::errorMessageOf<InputError>([&] { checkDimensions("v.raw", {most, most, most}); }), "");
}

TEST(MemoryBudget, TheCeilingCapsWhatIsAvailableUntilLifted) {
    {
        Ceiling ceiling(1u << 20);
        EXPECT_EQ(availableMemoryBytes(), 1u << 20);
    }
    EXPECT_GT(availableMemoryBytes(), 1u << 20);
}

TEST(MemoryBudget, AVolumeBeyondTheCeilingIsRefusedWithTheSizesByHand) {
    Ceiling ceiling(1u << 20);  // 0.000977 GiB
    // 32^3 uint8 samples and their float32 copy: 160 KiB.
    EXPECT_NO_THROW(checkVolumeFitsInMemory("f.nii", {32, 32, 32}, 1, 1));
    // 64^3 x (1 + 4) bytes = 1.25 MiB = 0.00122 GiB.
    EXPECT_EQ(test::errorMessageOf<InputError>([] {
                  checkVolumeFitsInMemory("f.nii", {64, 64, 64}, 1, 1, "export");
              }),
              "f.nii: a volume of 64x64x64 voxels needs 0.00122 GiB to export, but only 0.000977 GiB is available");
    // Only ingest can point to the formats that stream instead.
    const std::string ingest = test::errorMessageOf<InputError>([] {
        checkVolumeFitsInMemory("f.nii", {64, 64, 64}, 1, 1);
    });
    EXPECT_EQ(ingest.rfind("f.nii: a volume of 64x64x64 voxels needs 0.00122 GiB to ingest, but only 0.000977 GiB is "
                           "available; NIfTI, MGH, MetaImage and VDB volumes are read whole",
                           0),
              0u)
        << ingest;
    // 64 x 64 x 32 x (1 + 4) bytes fit; three channels of it, 1.9 MiB, do not.
    EXPECT_NO_THROW(checkVolumeFitsInMemory("f.nii", {64, 64, 32}, 1, 1));
    EXPECT_NE(test::errorMessageOf<InputError>([] { checkVolumeFitsInMemory("f.nii", {64, 64, 32}, 3, 1); }), "");
}

TEST(MemoryBudget, DimensionsAreCheckedBeforeMemory) {
    const std::string message = test::errorMessageOf<InputError>([] {
        checkVolumeFitsInMemory("f.nii", {0, 64, 64}, 1, 1);
    });
    EXPECT_NE(message.find("dimensions 0x64x64 are out of range"), std::string::npos) << message;
}

TEST(MemoryBudget, TheLargestDimensionsDoNotWrapAroundToASmallSize) {
    // 2^90 samples: a 64-bit product would wrap to 0 bytes and pass.
    const std::string message = test::errorMessageOf<InputError>([] {
        checkVolumeFitsInMemory("huge.mgz", {kLargest, kLargest, kLargest}, 3, 8);
    });
    EXPECT_EQ(message.rfind("huge.mgz: a volume of 1073741824x1073741824x1073741824 voxels needs ", 0), 0u) << message;
}

TEST(MemoryBudget, ASlabBeyondTheCeilingIsRefusedWithTheContextAppended) {
    Ceiling ceiling(1u << 20);
    // 64 x 64 x 16 x (2 + 4) bytes = 384 KiB.
    EXPECT_NO_THROW(checkSlabFitsInMemory("s.raw", {64, 64, 16}, 1, 2, "; slices 0..15"));
    // 256 x 256 x 16 x (2 + 4) bytes = 6 MiB = 0.00586 GiB.
    EXPECT_EQ(test::errorMessageOf<InputError>([] {
                  checkSlabFitsInMemory("s.raw", {256, 256, 16}, 1, 2, "; slices 0..15");
              }),
              "s.raw: one slab of 16 slices of 256x256 voxels needs 0.00586 GiB to stream, but only 0.000977 GiB "
              "is available; slices 0..15");
}

}  // namespace
}  // namespace gvr
