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

/// Writes a one-voxel grid with io::File, which adds delayed-load metadata, and
/// returns the file's bytes.
std::string oneVoxelFileBytes(const std::string& path) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
    grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
    grid->insertMeta("spacing", openvdb::Vec3DMetadata(openvdb::Vec3d(1, 2, 3)));
    openvdb::io::File(path).write({grid});
    return test::readBytes(path);
}

void expectRefused(const std::string& path, const std::string& message) {
    try {
        readGridFile(path);
        ADD_FAILURE() << "a corrupt file was read";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
    }
}

// Found by fuzz_vdb: a type name changed from vec3d to vec4d made OpenVDB read 32
// bytes of a 24-byte value, and every length after it from the wrong place (a
// 2 GiB string filled before the read failed).
TEST(GridFile, AMetadataValueOfTheWrongSizeForItsTypeIsRefused) {
    test::TempDir dir;
    std::string bytes = oneVoxelFileBytes(dir.path("g.vdb"));
    EXPECT_NO_THROW(readGridFile(dir.path("g.vdb")));
    const std::size_t type = bytes.find("vec3d");
    ASSERT_NE(type, std::string::npos);
    bytes[type + 3] = '4';
    test::writeBytes(dir.path("g.vdb"), bytes);
    expectRefused(dir.path("g.vdb"), "a 'vec4d' metadata value of 24 bytes (it takes 32)");
}

// Found by fuzz_vdb: the transform's map type name is one more string OpenVDB
// fills before its read can fail.
TEST(GridFile, ATransformTypeNamePastTheEndIsRefused) {
    test::TempDir dir;
    std::string bytes = oneVoxelFileBytes(dir.path("g.vdb"));
    const std::size_t name = bytes.find("UniformScaleMap");
    ASSERT_NE(name, std::string::npos);
    const std::uint32_t huge = 0xFFFFFFF0u;
    std::memcpy(&bytes[name - 4], &huge, sizeof huge);
    test::writeBytes(dir.path("g.vdb"), bytes);
    expectRefused(dir.path("g.vdb"), "a transform's map type claims 4294967280 bytes");
}

// OpenVDB sizes delayed-load metadata's arrays from a leaf count inside the value.
TEST(GridFile, DelayedLoadMetadataThatClaimsTooManyLeavesIsRefused) {
    test::TempDir dir;
    std::string bytes = oneVoxelFileBytes(dir.path("g.vdb"));
    const std::size_t type = bytes.find("__delayedload");
    ASSERT_NE(type, std::string::npos);
    const std::size_t count = type + std::strlen("__delayedload") + 4;  // after the value's size
    const std::uint32_t huge = 0x7FFFFFFFu;
    std::memcpy(&bytes[count], &huge, sizeof huge);
    test::writeBytes(dir.path("g.vdb"), bytes);
    expectRefused(dir.path("g.vdb"), "delayed-load metadata claims more leaf nodes than the file can hold");
}

}  // namespace
}  // namespace gvr
