// Benchmark manifests: JSON and TOML read alike, mistakes are named, shards partition the work.

#include "bench/BenchManifest.h"
#include "pipeline/Error.h"
#include "tests/TestHelpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

using namespace gvr;

namespace {

std::string write(const test::TempDir& dir, const std::string& name, const std::string& text) {
    std::ofstream(dir.path(name)) << text;
    return dir.path(name);
}

std::string manifestError(const std::string& path) {
    return test::errorMessageOf<InputError>([&] { readBenchManifest(path); });
}

const char* kJson = R"({
  "ratios": [10, 40],
  "methods": ["zfp-accuracy", "gvr", "vdb-half", "down3"],
  "fit": {"seconds": 30, "args": ["--batch", "4096"]},
  "render": {"size": "64x48", "views": 4, "elevation": 10},
  "volumes": [
    {"name": "head", "input": "data/head.nii.gz", "ingest": ["--spacing", "1,1,3.5"]},
    {"input": "/abs/ch2.nii.gz", "ratios": [5], "fit": {"iterations": 200}}
  ]
})";

const char* kToml = R"(
ratios = [10, 40]
methods = ["zfp-accuracy", "gvr", "vdb-half", "down3"]

[fit]
seconds = 30
args = ["--batch", "4096"]

[render]
size = "64x48"
views = 4
elevation = 10

[[volumes]]
name = "head"
input = "data/head.nii.gz"
ingest = ["--spacing", "1,1,3.5"]

[[volumes]]
input = "/abs/ch2.nii.gz"
ratios = [5]
fit = { iterations = 200 }
)";

}  // namespace

TEST(BenchManifest, JsonAndTomlGiveTheSameManifest) {
    test::TempDir dir;
    for (const std::string& path : {write(dir, "m.json", kJson), write(dir, "m.toml", kToml)}) {
        SCOPED_TRACE(path);
        const BenchManifest m = readBenchManifest(path);
        ASSERT_EQ(m.volumes.size(), 2u);
        EXPECT_EQ(m.volumes[0].name, "head");
        EXPECT_EQ(m.volumes[0].input, dir.path("data/head.nii.gz"));  // relative to the manifest
        EXPECT_EQ(m.volumes[0].ingestArgs, (std::vector<std::string>{"--spacing", "1,1,3.5"}));
        EXPECT_EQ(m.volumes[0].ratios, (std::vector<double>{10, 40}));
        EXPECT_EQ(m.volumes[0].fit.seconds, 30);
        EXPECT_FALSE(m.volumes[0].fit.iterations);
        EXPECT_EQ(m.volumes[1].name, "ch2");  // from the file name
        EXPECT_EQ(m.volumes[1].ratios, (std::vector<double>{5}));
        EXPECT_EQ(m.volumes[1].fit.iterations, std::optional<std::uint64_t>(200));
        EXPECT_EQ(m.volumes[1].fit.args, (std::vector<std::string>{"--batch", "4096"}));  // inherited
        EXPECT_EQ(m.render.size, "64x48");
        EXPECT_EQ(m.render.views, 4);
        EXPECT_EQ(m.render.elevation, 10);
    }
}

TEST(BenchManifest, UnitsRunGvrBeforeZfpAndRatioFreeMethodsOnce) {
    test::TempDir dir;
    const std::vector<BenchUnit> units = benchUnits(readBenchManifest(write(dir, "m.json", kJson)));
    // head: ratio-free, 10, 40; ch2: ratio-free, 5.
    ASSERT_EQ(units.size(), 5u);
    EXPECT_FALSE(units[0].ratio);
    EXPECT_EQ(units[0].methods, (std::vector<std::string>{"vdb-half", "down3"}));
    EXPECT_EQ(units[1].ratio, std::optional<double>(10));
    EXPECT_EQ(units[1].methods, (std::vector<std::string>{"gvr", "zfp-accuracy"}));
    EXPECT_EQ(units[4].volume, 1u);
    EXPECT_EQ(units[4].ratio, std::optional<double>(5));
}

TEST(BenchManifest, ShardsCoverEveryUnitExactlyOnce) {
    test::TempDir dir;
    const BenchManifest m = readBenchManifest(write(dir, "m.json", kJson));
    const std::size_t all = benchUnits(m).size();
    for (int shards : {1, 2, 3, 7}) {
        std::set<std::pair<std::size_t, double>> seen;
        std::size_t total = 0;
        for (int s = 0; s < shards; ++s) {
            for (const BenchUnit& u : benchUnits(m, s, shards)) {
                seen.insert({u.volume, u.ratio.value_or(-1)});
                ++total;
            }
        }
        EXPECT_EQ(total, all) << shards << " shards";
        EXPECT_EQ(seen.size(), all) << shards << " shards";
    }
}

TEST(BenchManifest, MistakesAreNamed) {
    test::TempDir dir;
    const auto volume = std::string(R"("volumes": [{"input": "a.nii"}])");
    EXPECT_NE(manifestError(write(dir, "a.json", R"({"methods": ["gvr", "sz3"], )" + volume + "}"))
                  .find("unknown method 'sz3'; known: gvr, gvr+bound, A1"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "b.json", R"({"ratio": [10], )" + volume + "}")).find("unknown key 'ratio'"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "c.json", R"({"ratios": [1], )" + volume + "}")).find("above 1"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "d.json", R"({"volumes": [{"input": "a.nii"}, {"input": "x/a.nii"}]})"))
                  .find("duplicate name 'a'"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "e.json", R"({"volumes": []})")).find("at least one volume"), std::string::npos);
    EXPECT_NE(manifestError(write(dir, "f.json", "{not json")).find("not valid JSON"), std::string::npos);
    EXPECT_NE(manifestError(write(dir, "g.toml", "ratios = [10\n")).find("not valid TOML"), std::string::npos);
    EXPECT_NE(manifestError(write(dir, "h.json", R"({"render": {"size": 64}, )" + volume + "}"))
                  .find("render.size: must be a string"),
              std::string::npos);
    EXPECT_NE(manifestError(dir.path("missing.json")).find("no such file"), std::string::npos);
    EXPECT_NE(manifestError(write(dir, "i.json", R"({"render": {"views": 0.5}, )" + volume + "}"))
                  .find("render.views: must be a whole number"),
              std::string::npos);
}

TEST(BenchManifest, CodecsAreDeclaredThenRunAfterGvrLikeAnyMethod) {
    test::TempDir dir;
    const std::string path = write(dir, "codecs.json", R"({
  "ratios": [10],
  "codecs": {"sz3": {"compress": ["sz3", "-i", "{input}", "-z", "{compressed}"],
                     "decompress": ["tools/unsz3", "{compressed}", "{output}"],
                     "param": [1e-6, 0.1], "version": ["sz3", "-v"], "timeout": 30}},
  "volumes": [{"input": "a.nii"}]
})");
    const BenchManifest manifest = readBenchManifest(path);
    ASSERT_EQ(manifest.codecs.size(), 1u);
    const ExternalCodec* sz3 = manifest.codec("sz3");
    ASSERT_NE(sz3, nullptr);
    EXPECT_EQ(manifest.codec("gvr"), nullptr);
    EXPECT_EQ(sz3->compress.front(), "sz3") << "a bare name is looked up on PATH when the run starts";
    EXPECT_EQ(sz3->decompress.front(), dir.path("tools/unsz3")) << "a path is relative to the manifest";
    EXPECT_DOUBLE_EQ(sz3->paramMin, 1e-6);
    EXPECT_DOUBLE_EQ(sz3->timeoutSeconds, 30);
    EXPECT_EQ(sz3->versionCommand, (std::vector<std::string>{"sz3", "-v"}));
    // Without "methods", every method runs but gvr+bound (a second fit), the codec
    // last: it matches gvr's bytes.
    EXPECT_EQ(manifest.methods.back(), "sz3");
    EXPECT_EQ(std::count(manifest.methods.begin(), manifest.methods.end(), "gvr+bound"), 0);
    const std::vector<BenchUnit> units = benchUnits(manifest);
    ASSERT_EQ(units.size(), 2u);
    EXPECT_EQ(units[1].methods.front(), "gvr");
    EXPECT_EQ(units[1].methods.back(), "sz3");
}

TEST(BenchManifest, CodecMistakesAreNamed) {
    test::TempDir dir;
    const auto manifest = [&](const std::string& name, const std::string& codec) {
        return write(dir, name, R"({"codecs": {"c": )" + codec + R"(}, "volumes": [{"input": "a.nii"}]})");
    };
    const std::string commands = R"("compress": ["c", "{input}"], "decompress": ["d", "{output}"])";
    EXPECT_NE(
        manifestError(manifest("a.json", "{" + commands + "}")).find("codecs.c.param: must be [smallest, largest]"),
        std::string::npos);
    EXPECT_NE(
        manifestError(manifest("b.json", "{" + commands + R"(, "param": [1, 0.5]})")).find("smallest must lie below"),
        std::string::npos);
    EXPECT_NE(manifestError(manifest("c.json", "{" + commands + R"(, "param": [0, 1]})")).find("positive"),
              std::string::npos);
    EXPECT_NE(manifestError(manifest("d.json", R"({"compress": [], "decompress": ["d"], "param": [1, 2]})"))
                  .find("codecs.c.compress: must start with the program"),
              std::string::npos);
    EXPECT_NE(manifestError(manifest("e.json", "{" + commands + R"(, "param": [1, 2], "level": 3})"))
                  .find("unknown key 'level'"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "f.json", R"({"codecs": {"gvr": {}}, "volumes": [{"input": "a.nii"}]})"))
                  .find("codecs.gvr: is a built-in method's name"),
              std::string::npos);
    EXPECT_NE(manifestError(write(dir, "g.json", R"({"codecs": {"a|b": {}}, "volumes": [{"input": "a.nii"}]})"))
                  .find("codecs.a|b: 'a|b' is not a name"),
              std::string::npos);
    EXPECT_NE(manifestError(manifest("h.json", "{" + commands + R"(, "param": [1, 2], "timeout": -1})"))
                  .find("codecs.c.timeout"),
              std::string::npos);
}

// Names become folders: ".." once made a row write beside the results folder, a '/'
// let one row's folder hold another's, and 300 characters failed with "File name too long".
TEST(BenchManifest, NamesThatWouldBePathsAreRefused) {
    test::TempDir dir;
    const auto volumeNamed = [&](const std::string& name) {
        return manifestError(write(dir, "v.json", R"({"volumes": [{"name": ")" + name + R"(", "input": "a.nii"}]})"));
    };
    for (const std::string& name : {std::string("."), std::string(".."), std::string("a/b"), std::string(".hidden"),
                                    std::string(300, 'x'), std::string("two words"), std::string("")}) {
        EXPECT_NE(volumeNamed(name).find("volumes[0].name: '" + name + "' is not a name"), std::string::npos) << name;
    }
    EXPECT_EQ(volumeNamed("ct-head_2.5+x"), "");
    EXPECT_EQ(volumeNamed(std::string(64, 'x')), "");
    EXPECT_NE(manifestError(write(dir, "c.json", R"({"codecs": {"../up": {}}, "volumes": [{"input": "a.nii"}]})"))
                  .find("codecs.../up: '../up' is not a name"),
              std::string::npos);
}

// The JSON parser keeps a repeated key's last value without a word.
TEST(BenchManifest, AKeyTwiceInOneObjectIsRefused) {
    test::TempDir dir;
    EXPECT_NE(
        manifestError(write(dir, "a.json", R"({"ratios": [10], "ratios": [20], "volumes": [{"input": "a.nii"}]})"))
            .find("the key 'ratios' appears twice in one object"),
        std::string::npos);
    EXPECT_NE(
        manifestError(write(dir, "b.json", R"({"volumes": [{"input": "a.nii", "fit": {"seconds": 1, "seconds": 2}}]})"))
            .find("the key 'seconds' appears twice"),
        std::string::npos);
    // The same key in sibling objects, and in an object and its parent, is no repeat.
    EXPECT_EQ(manifestError(write(dir, "c.json", R"({"fit": {"seconds": 1}, "volumes": [{"name": "a", "input": "a.nii",
               "fit": {"seconds": 2}}, {"name": "b", "input": "b.nii", "fit": {"seconds": 3}}]})")),
              "");
}

// With six digits, 8 and 8.0000001 were one row; the same ratio twice is a mistake.
TEST(BenchManifest, RatiosKeepRowsOfTheirOwnAndAreNotRepeated) {
    test::TempDir dir;
    const BenchManifest manifest = readBenchManifest(write(
        dir, "a.json", R"({"ratios": [8, 8.0000001, 7.5], "methods": ["gvr"], "volumes": [{"input": "a.nii"}]})"));
    std::set<std::string> texts;
    for (const BenchUnit& unit : benchUnits(manifest)) texts.insert(ratioText(unit.ratio));
    EXPECT_EQ(texts, (std::set<std::string>{"8", "8.0000001", "7.5"}));
    EXPECT_NE(manifestError(write(dir, "b.json", R"({"ratios": [8, 8.0], "volumes": [{"input": "a.nii"}]})"))
                  .find("ratios: lists 8 twice"),
              std::string::npos);
}

TEST(BenchManifest, ViewSizesBeyondWhatTheBenchComparesAreRefused) {
    test::TempDir dir;
    const auto sized = [&](const std::string& size) {
        return manifestError(
            write(dir, "s.json", R"({"render": {"size": ")" + size + R"("}, "volumes": [{"input": "a.nii"}]})"));
    };
    for (const char* size : {"100000x100000", "4096x16", "0x16", "16", "16x16x16", "wide"}) {
        EXPECT_NE(sized(size).find("render.size: '" + std::string(size) + "' is not WIDTHxHEIGHT of 1 to 2048"),
                  std::string::npos)
            << size;
    }
    EXPECT_EQ(sized("2048x2048"), "");
}

TEST(BenchManifest, AManifestThatIsNotUtf8IsRefusedInOneLine) {
    test::TempDir dir;
    const std::string message =
        manifestError(write(dir, "a.json", "{\"volumes\": [{\"name\": \"ch\xff\xfe\", \"input\": \"a.nii\"}]}"));
    EXPECT_NE(message.find("not valid JSON"), std::string::npos) << message;
}

TEST(BenchManifest, TheExampleManifestsRead) {
    const std::filesystem::path examples = std::filesystem::path(GVR_TEST_DATA) / ".." / ".." / "examples";
    std::size_t read = 0;
    for (const auto& entry : std::filesystem::directory_iterator(examples)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("bench-", 0) != 0 || entry.path().extension() != ".json") continue;
        SCOPED_TRACE(name);
        EXPECT_NO_THROW(readBenchManifest(entry.path().string()));
        ++read;
    }
    EXPECT_GE(read, 5u);
    const BenchManifest codecs = readBenchManifest((examples / "bench-codecs.json").string());
    EXPECT_EQ(codecs.methods, (std::vector<std::string>{"gvr", "zfp-accuracy", "sz3", "sperr"}));
    EXPECT_NE(codecs.codec("sperr"), nullptr);
}
