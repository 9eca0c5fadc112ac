#include "AtomicFile.h"
#include "Error.h"
#include "GridFile.h"
#include "Ingest.h"
#include "TestHelpers.h"
#include "VolumeMetadata.h"

#include <filesystem>

namespace gvr {
namespace {

TEST(GridFile, RoundTripIsBitExact) {
    GVR_REQUIRE_SHARED_DATA();
    test::TempDir dir;
    const IngestResult ingested = ingest(test::sharedData("ct-chest-ricord-512"), {});
    writeGridFile(dir.path("chest.vdb"), {ingested.grid});
    const openvdb::GridPtrVecPtr grids = readGridFile(dir.path("chest.vdb"));
    ASSERT_EQ(grids->size(), 1u);
    auto original = openvdb::GridBase::grid<openvdb::FloatGrid>(ingested.grid);
    auto reread = openvdb::GridBase::grid<openvdb::FloatGrid>(grids->front());
    ASSERT_TRUE(original && reread);
    EXPECT_EQ(reread->activeVoxelCount(), original->activeVoxelCount());
    EXPECT_EQ(reread->transform(), original->transform());
    EXPECT_EQ(reread->background(), original->background());
    auto accessor = reread->getConstAccessor();
    std::size_t mismatches = 0;
    for (auto value = original->cbeginValueOn(); value; ++value) {
        const float got = accessor.getValue(value.getCoord());
        mismatches += std::memcmp(&got, &*value, sizeof got) != 0 || !accessor.isValueOn(value.getCoord());
    }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(readVolumeMetadata(*reread)->dims, readVolumeMetadata(*original)->dims);
    EXPECT_EQ(readVolumeMetadata(*reread)->modality, "CT");
}

TEST(GridFile, FailedWriteLeavesNoFile) {
    test::TempDir dir;
    const std::string target = dir.path("out.vdb");
    EXPECT_THROW(writeAtomically(target,
                                 [](const std::string& temporary) {
                                     test::writeBytes(temporary, "half a file");
                                     throw InputError("out.vdb", "simulated failure");
                                 }),
                 InputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.root()));
}

TEST(GridFile, RejectsFilesThatAreNotVdb) {
    test::TempDir dir;
    test::writeBytes(dir.path("fake.vdb"), "definitely not a vdb file");
    EXPECT_THROW(readGridFile(dir.path("fake.vdb")), InputError);
    try {
        readGridFile(dir.path("missing.vdb"));
        ADD_FAILURE() << "a missing file was read";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("no such file"), std::string::npos) << error.what();
    }
}

}  // namespace
}  // namespace gvr
