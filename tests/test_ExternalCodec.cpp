// External codecs as benchmark baselines, run through tests/fake_codec.py: the
// size search, the raw layout's axis order, colour channels, and every way a
// codec can misbehave, each a one-line CodecFailure.

#include "bench/ExternalCodec.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

using namespace gvr;

namespace {

const std::string kPython = "/usr/bin/python3";
const std::string kFakeCodec = std::string(GVR_TEST_DATA) + "/../fake_codec.py";

ExternalCodec fakeCodec(const std::string& compressMode, const std::string& decompressMode = "quantise") {
    ExternalCodec codec;
    codec.name = "fake";
    codec.compress = {kPython, kFakeCodec, "c",    compressMode, "{input}",
                      "{nx}",  "{ny}",     "{nz}", "{param}",    "{compressed}"};
    codec.decompress = {kPython, kFakeCodec, "d", decompressMode, "{compressed}", "{output}", "{nx}", "{ny}", "{nz}"};
    codec.paramMin = 1e-4;
    codec.paramMax = 10;
    codec.timeoutSeconds = 60;
    return codec;
}

/// A smooth volume of @a channels channels on a lattice with three different sides.
FloatVolume smoothVolume(int channels = 1) {
    FloatVolume volume(openvdb::Coord(12, 9, 7), channels);
    for (int k = 0; k < 7; ++k) {
        for (int j = 0; j < 9; ++j) {
            for (int i = 0; i < 12; ++i) {
                for (int c = 0; c < channels; ++c) {
                    volume.at(i, j, k)[c] = float(100.0 * std::sin(0.3 * i + 0.2 * j) * std::cos(0.25 * k) + 40.0 * c);
                }
            }
        }
    }
    return volume;
}

struct CodecRun {
    test::TempDir dir;
    RawChannels raw;

    explicit CodecRun(const FloatVolume& volume) { raw = writeRawChannels(volume, dir.path("")); }

    CodecResult run(const ExternalCodec& codec, std::uint64_t target) {
        std::filesystem::create_directories(dir.path("run"));
        return runExternalCodec(codec, raw, target, dir.path("run"), dir.path("log.txt"));
    }

    /// The CodecFailure's message, or "" when the run succeeded.
    std::string failure(const ExternalCodec& codec, std::uint64_t target = 1000) {
        return test::errorMessageOf<CodecFailure>([&] { run(codec, target); });
    }
};

double largestError(const FloatVolume& volume, const std::vector<float>& values) {
    double largest = 0;
    for (std::size_t v = 0; v < values.size(); ++v)
        largest = std::max(largest, double(std::abs(values[v] - volume.values[v])));
    return largest;
}

}  // namespace

TEST(ExternalCodec, TheSearchMatchesTheTargetSizeAndTheErrorFollowsTheParameter) {
    const FloatVolume volume = smoothVolume();
    CodecRun codec(volume);
    for (const std::uint64_t target : {700u, 1300u}) {
        SCOPED_TRACE(target);
        const CodecResult result = codec.run(fakeCodec("quantise"), target);
        EXPECT_TRUE(result.matched);
        EXPECT_NEAR(double(result.bytes) / target, 1.0, 0.05);
        EXPECT_EQ(result.bytes, std::filesystem::file_size(codec.dir.path("run/compressed.c0")));
        ASSERT_EQ(result.values.size(), volume.values.size());
        // The quantiser's step is the parameter: no value moves by more than half of it.
        EXPECT_LE(largestError(volume, result.values), 0.5 * result.param * 1.0001 + 1e-4);
        EXPECT_GT(largestError(volume, result.values), 0.0);
    }
}

TEST(ExternalCodec, ASizeThatJumpsPastTheTargetEndsTheSearchWithTheClosest) {
    const FloatVolume volume = smoothVolume();
    CodecRun codec(volume);
    // Steps of 4^k: the sizes at neighbouring steps differ by far more than 5 %.
    const CodecResult result = codec.run(fakeCodec("steps"), 850);
    EXPECT_FALSE(result.matched);
    EXPECT_EQ(result.bytes, std::filesystem::file_size(codec.dir.path("run/compressed.c0")));
    std::ifstream log(codec.dir.path("log.txt"));
    std::set<std::string> params;
    std::size_t trials = 0;
    for (std::string line; std::getline(log, line);) {
        if (line.rfind("fake: param ", 0) != 0) continue;
        ++trials;
        EXPECT_TRUE(params.insert(line.substr(0, line.find(" ->"))).second) << "tried twice: " << line;
    }
    EXPECT_GE(trials, 3u);
    EXPECT_LE(trials, 16u);
    EXPECT_LE(largestError(volume, result.values), 0.5 * result.param * 1.0001 + 1e-4);
}

TEST(ExternalCodec, RawFilesHoldTheFastestAxisFirstAsTheNxPlaceholderSays) {
    // Constant along i (x), different in every row: a codec that keeps the first value
    // of each NX-long row gives it back exactly only if rows in the file run along x.
    FloatVolume volume(openvdb::Coord(6, 5, 4), 1);
    for (int k = 0; k < 4; ++k) {
        for (int j = 0; j < 5; ++j) {
            for (int i = 0; i < 6; ++i) *volume.at(i, j, k) = float(j + 10 * k);
        }
    }
    CodecRun codec(volume);
    const CodecResult right = codec.run(fakeCodec("first-x", "first-x"), 100);
    EXPECT_EQ(largestError(volume, right.values), 0.0);

    ExternalCodec swapped = fakeCodec("first-x", "first-x");
    for (auto* args : {&swapped.compress, &swapped.decompress}) {
        std::swap(*std::find(args->begin(), args->end(), "{nx}"), *std::find(args->begin(), args->end(), "{nz}"));
    }
    EXPECT_GT(largestError(volume, codec.run(swapped, 100).values), 1.0) << "the test must see a wrong axis order";
}

TEST(ExternalCodec, ColourRunsPerChannelAndAddsTheBytes) {
    const FloatVolume volume = smoothVolume(3);
    CodecRun codec(volume);
    ASSERT_EQ(codec.raw.files.size(), 3u);
    const CodecResult result = codec.run(fakeCodec("quantise"), 1500);
    std::uint64_t bytes = 0;
    for (int c = 0; c < 3; ++c)
        bytes += std::filesystem::file_size(codec.dir.path("run/compressed.c" + std::to_string(c)));
    EXPECT_EQ(result.bytes, bytes);
    // Channels come back interleaved, each in its own range (channel c is offset by 40 c).
    EXPECT_LE(largestError(volume, result.values), 0.5 * result.param * 1.0001 + 1e-4);
}

TEST(ExternalCodec, EveryMisbehaviourIsAOneLineFailure) {
    CodecRun codec(smoothVolume());
    ExternalCodec unknown = fakeCodec("quantise");
    unknown.compress.push_back("--level={level}");
    EXPECT_NE(codec.failure(unknown).find("unknown placeholder {level}"), std::string::npos);

    const std::string failed = codec.failure(fakeCodec("fail"));
    EXPECT_NE(failed.find("compress"), std::string::npos) << failed;
    EXPECT_NE(failed.find("exit 3"), std::string::npos) << failed;
    EXPECT_NE(failed.find("failing on purpose"), std::string::npos) << failed;

    ExternalCodec hangs = fakeCodec("hang");
    hangs.timeoutSeconds = 1;
    const auto start = std::chrono::steady_clock::now();
    EXPECT_NE(codec.failure(hangs).find("time limit of 1 s"), std::string::npos);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
    // The limit is the row's: three runs of 0.4 s each pass it, though none alone does.
    ExternalCodec slow = fakeCodec("slow");
    slow.timeoutSeconds = 1;
    EXPECT_NE(codec.failure(slow).find("the row's time limit of 1 s"), std::string::npos);

    EXPECT_NE(codec.failure(fakeCodec("nothing")).find("compress (channel 0, param"), std::string::npos);
    EXPECT_NE(codec.failure(fakeCodec("nothing")).find("wrote no file"), std::string::npos);
    EXPECT_NE(codec.failure(fakeCodec("quantise", "nothing")).find("decompress"), std::string::npos);
    EXPECT_NE(codec.failure(fakeCodec("quantise", "short")).find("12 x 9 x 7 float32 voxels are 3024"),
              std::string::npos);
    EXPECT_NE(codec.failure(fakeCodec("quantise", "nan")).find("non-finite value at voxel 252"), std::string::npos);

    ExternalCodec missing = fakeCodec("quantise");
    missing.compress.front() = "no-such-codec-program";
    EXPECT_NE(codec.failure(missing).find("'no-such-codec-program' not found"), std::string::npos);
    for (const std::string& message :
         {codec.failure(fakeCodec("fail")), codec.failure(fakeCodec("quantise", "short")), codec.failure(hangs)}) {
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(ExternalCodec, FindProgramLooksOnThePathAndTakesPathsAsGiven) {
    EXPECT_FALSE(findProgram("sh").empty());
    EXPECT_EQ(findProgram(kPython), kPython);
    EXPECT_EQ(findProgram("no-such-program-anywhere"), "");
    EXPECT_EQ(findProgram("/no/such/program"), "");
    EXPECT_EQ(findProgram(kFakeCodec.substr(0, kFakeCodec.size() - 3)), "") << "not a file";
}
