#include "io/Ingest.h"
#include "io/formats/GridFile.h"
#include "io/guard/AtomicFile.h"
#include "pipeline/Error.h"
#include "pipeline/VolumeMetadata.h"
#include "tests/TestHelpers.h"

#include <openvdb/io/File.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <type_traits>

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

TEST(GridFile, OnDemandReadsOnlyTheLeavesTouchedAndTheSameValues) {
    test::TempDir dir;
    const openvdb::GridBase::Ptr written =
        test::makeGrid({40, 32, 24}, [](int i, int j, int k) { return float(1 + i + 100 * j + 10000 * k); });
    writeGridFile(dir.path("g.vdb"), {written});
    const auto original = openvdb::GridBase::grid<openvdb::FloatGrid>(written);
    const auto mapped = openvdb::GridBase::grid<openvdb::FloatGrid>(readGridFileOnDemand(dir.path("g.vdb"))->front());
    ASSERT_TRUE(original && mapped);
    EXPECT_EQ(mapped->activeVoxelCount(), original->activeVoxelCount());  // from the masks alone

    const auto leavesInMemory = [&] {
        std::size_t loaded = 0;
        for (auto leaf = mapped->tree().cbeginLeaf(); leaf; ++leaf) loaded += !leaf->buffer().isOutOfCore();
        return loaded;
    };
    EXPECT_EQ(leavesInMemory(), 0u);
    const openvdb::Coord inside(9, 17, 5);
    EXPECT_EQ(mapped->tree().getValue(inside), original->tree().getValue(inside));
    EXPECT_EQ(leavesInMemory(), 1u);

    auto accessor = mapped->getConstAccessor();
    for (auto value = original->cbeginValueOn(); value; ++value) {
        ASSERT_EQ(accessor.getValue(value.getCoord()), *value) << value.getCoord();
    }
    EXPECT_EQ(leavesInMemory(), original->tree().leafCount());
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

TEST(GridFile, AFrustumTransformIsRefusedNotReadAsTheIdentity) {
    test::TempDir dir;
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->tree().setValueOn(openvdb::Coord(1, 2, 3), 5.0f);
    grid->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0.0), openvdb::Vec3d(10.0)), /*taper=*/0.5, /*depth=*/20.0));
    writeGridFile(dir.path("frustum.vdb"), {grid});
    try {
        readGridFile(dir.path("frustum.vdb"));
        ADD_FAILURE() << "a frustum transform was read";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("non-linear (frustum) transform"), std::string::npos) << error.what();
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

/// Writes oneVoxelFileBytes(), overwrites it with @a patch @a offset bytes after
/// the first @a marker, and expects the read to be refused with @a message.
template <typename T>
void expectPatchRefused(const std::string& marker, std::ptrdiff_t offset, const T& patch, const std::string& message) {
    test::TempDir dir;
    const std::string path = dir.path("g.vdb");
    std::string bytes = oneVoxelFileBytes(path);
    EXPECT_NO_THROW(readGridFile(path));
    const std::size_t at = bytes.find(marker);
    ASSERT_NE(at, std::string::npos) << marker;
    std::memcpy(&bytes[std::size_t(std::ptrdiff_t(at) + offset)], &patch, sizeof patch);
    test::writeBytes(path, bytes);
    expectRefused(path, message);
}

// Found by fuzz_vdb: a type name changed from vec3d to vec4d made OpenVDB read 32
// bytes of a 24-byte value, and every length after it from the wrong place (a
// 2 GiB string filled before the read failed).
TEST(GridFile, AMetadataValueOfTheWrongSizeForItsTypeIsRefused) {
    expectPatchRefused("vec3d", 3, '4', "a 'vec4d' metadata value of 24 bytes (it takes 32)");
}

// Found by fuzz_vdb: the transform's map type name is one more string OpenVDB
// fills before its read can fail.
TEST(GridFile, ATransformTypeNamePastTheEndIsRefused) {
    expectPatchRefused("UniformScaleMap", -4, std::uint32_t(0xFFFFFFF0u),
                       "a transform's map type claims 4294967280 bytes");
}

// OpenVDB sizes delayed-load metadata's arrays from a leaf count inside the value.
TEST(GridFile, DelayedLoadMetadataThatClaimsTooManyLeavesIsRefused) {
    const std::ptrdiff_t count = std::strlen("__delayedload") + 4;  // after the value's size
    expectPatchRefused("__delayedload", count, std::uint32_t(0x7FFFFFFFu),
                       "delayed-load metadata claims more leaf nodes than the file can hold");
}

/// A grid of @a GridT with one full leaf of random values (of random bits for
/// integers, which zlib cannot shrink and stores raw), an inactive voxel, a tile
/// and 100 one-voxel leaves, written with
/// @a compression; returns the file's bytes.
template <typename GridT>
std::string writeSampleGrid(const std::string& path, std::uint32_t compression, bool half = false) {
    using ValueT = typename GridT::ValueType;
    typename GridT::Ptr grid = GridT::create();
    std::uint32_t state = 12345;
    for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) {
            for (int k = 0; k < 8; ++k) {
                ValueT value;
                for (std::size_t b = 0; b < sizeof value; b += 4) {
                    state = state * 1664525u + 1013904223u;
                    std::uint32_t bits = state;
                    if (std::is_floating_point<typename openvdb::VecTraits<ValueT>::ElementType>::value) {
                        bits = (bits & 0x3FFFFFFFu) | 0x3E000000u;  // finite
                    }
                    std::memcpy(reinterpret_cast<char*>(&value) + b, &bits, std::min<std::size_t>(4, sizeof value - b));
                }
                grid->tree().setValue(openvdb::Coord(i, j, k), value);
            }
        }
    }
    grid->tree().setValueOff(openvdb::Coord(100, 0, 0), openvdb::zeroVal<ValueT>());
    // 100 more leaves: delayed-load metadata compresses, and pads, arrays of 48-128 bytes.
    for (int leaf = 0; leaf < 100; ++leaf) grid->tree().setValue(openvdb::Coord(8 * leaf, 64, 0), ValueT(1));
    grid->tree().addTile(1, openvdb::Coord(4096, 0, 0), openvdb::zeroVal<ValueT>(), true);
    grid->setSaveFloatAsHalf(half);
    openvdb::io::File file(path);
    file.setCompression(compression);
    file.write({grid});
    return test::readBytes(path);
}

void expectReadable(const std::string& path) {
    try {
        readGridFile(path);
    } catch (const InputError& error) {
        ADD_FAILURE() << error.what();
    }
}

TEST(GridFile, EveryStoredLayoutOfTheValueTypesGvrReadsPassesTheChecks) {
    using namespace openvdb::io;
    test::TempDir dir;
    const std::string path = dir.path("g.vdb");
    for (std::uint32_t compression : std::initializer_list<std::uint32_t>{
             COMPRESS_NONE, COMPRESS_ZIP, COMPRESS_BLOSC, COMPRESS_ACTIVE_MASK, COMPRESS_ZIP | COMPRESS_ACTIVE_MASK,
             COMPRESS_BLOSC | COMPRESS_ACTIVE_MASK}) {
        SCOPED_TRACE(compressionToString(compression));
        for (bool half : {false, true}) {
            writeSampleGrid<openvdb::FloatGrid>(path, compression, half);
            expectReadable(path);
            writeSampleGrid<openvdb::Vec3SGrid>(path, compression, half);
            expectReadable(path);
            writeSampleGrid<openvdb::DoubleGrid>(path, compression, half);
            expectReadable(path);
        }
        writeSampleGrid<openvdb::Int32Grid>(path, compression);
        expectReadable(path);
    }
}

// Found by fuzz_vdb: Debian's OpenVDB 10 reads an uncompressed block of the size
// the file states into a buffer of the size it expects (a segfault in release).
TEST(GridFile, AnUncompressedBlockOfTheWrongSizeIsRefused) {
    test::TempDir dir;
    std::string bytes = writeSampleGrid<openvdb::Int32Grid>(dir.path("g.vdb"), openvdb::io::COMPRESS_ZIP);
    expectReadable(dir.path("g.vdb"));
    const std::int64_t raw = -2048, larger = -4096;  // 512 integers, stored raw
    const std::size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&raw), sizeof raw));
    ASSERT_NE(at, std::string::npos);
    std::memcpy(&bytes[at], &larger, sizeof larger);
    test::writeBytes(dir.path("g.vdb"), bytes);
    expectRefused(dir.path("g.vdb"), "an uncompressed block of 4096 bytes where 2048 belong");
}

// Found by fuzz_vdb: a scale of zero made the transform singular, and OpenVDB
// threw (an internal error, exit 1) only when the reader asked for its matrix.
TEST(GridFile, ASingularTransformIsRefused) {
    // A UniformScaleMap stores its scale (1, 1, 1 here) right after its name.
    const std::ptrdiff_t scale = std::strlen("UniformScaleMap");
    expectPatchRefused("UniformScaleMap", scale, std::array<double, 3>{0.0, 0.0, 0.0},
                       "grid '' has a singular or non-finite transform");
}

TEST(GridFile, GridTypesAndVersionsTheChecksCannotWalkAreRefused) {
    test::TempDir dir;
    openvdb::BoolGrid::Ptr mask = openvdb::BoolGrid::create();
    mask->tree().setValue(openvdb::Coord(1, 2, 3), true);
    mask->setName("mask");
    openvdb::io::File(dir.path("b.vdb")).write({mask});
    expectRefused(dir.path("b.vdb"), "grid 'mask' is a Tree_bool_5_4_3, a type gvr does not read");

    std::string bytes = oneVoxelFileBytes(dir.path("old.vdb"));
    const std::uint32_t version = 221;  // just before node mask compression
    std::memcpy(&bytes[8], &version, sizeof version);
    test::writeBytes(dir.path("old.vdb"), bytes);
    expectRefused(dir.path("old.vdb"), "VDB format version 221");
}

// gvr eval of a grid whose gvr_dims claimed 2e9^3 voxels ended in exit 1, "cannot
// create std::vector larger than max_size()": metadata sizes what readers allocate.
TEST(GridFile, AbsurdVolumeMetadataIsRefusedLikeAHeader) {
    test::TempDir dir;
    const auto refusedWith = [&](const std::function<void(VolumeMetadata&)>& spoil, const std::string& message) {
        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create();
        grid->setName("density");
        grid->tree().setValue(openvdb::Coord(1, 2, 3), 1.0f);
        VolumeMetadata metadata;
        metadata.sourceType = "uint8";
        metadata.dims = openvdb::Vec3i(4, 4, 4);
        spoil(metadata);
        writeVolumeMetadata(metadata, *grid);
        openvdb::io::File(dir.path("m.vdb")).write({grid});
        expectRefused(dir.path("m.vdb"), message);
    };
    refusedWith([](VolumeMetadata& m) { m.dims = openvdb::Vec3i(2000000000, 2000000000, 2000000000); },
                "gvr_dims metadata): dimensions 2000000000x2000000000x2000000000 are out of range");
    refusedWith([](VolumeMetadata& m) { m.dims = openvdb::Vec3i(4, 0, 4); }, "dimensions 4x0x4 are out of range");
    refusedWith([](VolumeMetadata& m) { m.channels = 7; }, "has gvr_channels 7; gvr writes 1 or 3");
    refusedWith([](VolumeMetadata& m) { m.spacingMm = openvdb::Vec3d(1.0, std::nan(""), 1.0); },
                "gvr_spacing_mm that is not a positive finite size");
}

// Found by fuzz_vdb: an integer grid named "density" was chosen as the volume, and
// the reader then read it as a Vec3s grid through a null pointer.
TEST(GridFile, OnlyGridsOfAValueTypeGvrReadsAreChosenAsTheVolume) {
    openvdb::Int32Grid::Ptr integers = openvdb::Int32Grid::create();
    integers->setName("density");
    writeVolumeMetadata(VolumeMetadata{}, *integers);
    openvdb::FloatGrid::Ptr floats = openvdb::FloatGrid::create();
    floats->setName("other");
    EXPECT_EQ(chooseVolumeGrid({integers, floats}, "g.vdb"), floats);
    try {
        chooseVolumeGrid({integers}, "g.vdb");
        ADD_FAILURE() << "an integer grid was chosen as the volume";
    } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("holds no float, double or Vec3s grid; found: density (int32)"),
                  std::string::npos)
            << error.what();
    }
}

}  // namespace
}  // namespace gvr
