#include "AtomicFile.h"
#include "Error.h"
#include "GridFile.h"
#include "Ingest.h"
#include "TestHelpers.h"
#include "VolumeMetadata.h"

#include <openvdb/io/File.h>

#include <cstring>
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

// Found by fuzz_vdb: OpenVDB filled a 4 GiB string from a corrupt metadata length
// before its read failed. Every length in the headers is checked first.
TEST(GridFile, ALengthPastTheEndIsRefusedBeforeOpenVdbAllocatesIt) {
    test::TempDir dir;
    for (const char* name : {"file_note", "grid_note"}) {
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
        grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
        grid->insertMeta("grid_note", openvdb::StringMetadata("a value to corrupt"));
        openvdb::MetaMap fileMetadata;
        fileMetadata.insertMeta("file_note", openvdb::StringMetadata("a value to corrupt"));
        openvdb::io::File(dir.path("g.vdb")).write({grid}, fileMetadata);
        EXPECT_NO_THROW(readGridFile(dir.path("g.vdb"))) << name;

        std::string bytes = test::readBytes(dir.path("g.vdb"));
        const std::size_t value = bytes.find("a value to corrupt", bytes.find(name));
        ASSERT_NE(value, std::string::npos) << name;
        const std::uint32_t huge = 0xF0000000u;
        std::memcpy(&bytes[value - 4], &huge, sizeof huge);
        test::writeBytes(dir.path("g.vdb"), bytes);
        try {
            readGridFile(dir.path("g.vdb"));
            ADD_FAILURE() << name << ": a corrupt length was read";
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find("a metadata value claims 4026531840 bytes"), std::string::npos)
                << error.what();
        }
    }
}

}  // namespace
}  // namespace gvr
