// Labels end to end: ingest checks the label grid against the image, fit keeps a
// label per Gaussian with per-structure budgets, render and export select
// structures without refitting, eval reports each structure.

#include "io/asset/AssetFile.h"
#include "io/formats/ImageFile.h"
#include "io/formats/NiftiWriter.h"
#include "pipeline/FloatVolume.h"
#include "tests/TestHelpers.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

using namespace gvr;
using test::runGvr;

namespace {

/// Two blobs, labelled 1 ("Left") and 2 ("Right"), in a 32 x 20 x 16 volume.
struct LabelledScene {
    std::string image, labels, names, grid;
};

LabelledScene writeScene(const test::TempDir& dir) {
    const openvdb::Coord dims(32, 20, 16);
    FloatVolume image(dims, 1), labels(dims, 1);
    for (int k = 0; k < dims.z(); ++k) {
        for (int j = 0; j < dims.y(); ++j) {
            for (int i = 0; i < dims.x(); ++i) {
                const double left = (i - 9) * (i - 9) + (j - 10) * (j - 10) + (k - 8) * (k - 8);
                const double right = (i - 23) * (i - 23) + (j - 10) * (j - 10) + (k - 8) * (k - 8);
                *image.at(i, j, k) = float(200.0 * std::exp(-left / 18.0) + 120.0 * std::exp(-right / 12.0));
                *labels.at(i, j, k) = left < 36 ? 1.0f : right < 25 ? 2.0f : 0.0f;
            }
        }
    }
    LabelledScene scene{dir.path("image.nii"), dir.path("labels.nii"), dir.path("names.txt"), dir.path("scene.vdb")};
    writeNifti(scene.image, image);
    writeNifti(scene.labels, labels);
    std::ofstream(scene.names) << "# id name code\n1 Left 1001\n2 Right 1002\n";
    return scene;
}

class CliLabels : public ::testing::Test {
protected:
    void SetUp() override {
        scene = writeScene(dir);
        const test::CommandResult run = runGvr("ingest -q '" + scene.image + "' -o '" + scene.grid + "' --labels '" +
                                                   scene.labels + "' --label-names '" + scene.names + "' --json",
                                               dir);
        ASSERT_EQ(run.exitCode, 0) << run.err;
        EXPECT_EQ(nlohmann::json::parse(run.out)["labels"], (nlohmann::json{{"1", "Left"}, {"2", "Right"}}));
    }

    test::CommandResult fit(const std::string& labels, const std::string& asset, const std::string& extra = "") {
        return runGvr("fit -q '" + scene.grid + "' -o '" + dir.path(asset) + "' --labels " + labels +
                          " --iterations 40 --batch 2048 --threads 1 --json " + extra,
                      dir);
    }

    std::vector<float> render(const std::string& asset, const std::string& extra, const std::string& png) {
        const test::CommandResult run = runGvr(
            "render -q '" + dir.path(asset) + "' -o '" + dir.path(png) + "' --size 48x48 --tf '" + tf() + "' " + extra,
            dir);
        EXPECT_EQ(run.exitCode, 0) << run.err;
        auto in = OIIO::ImageInput::open(dir.path(png));
        std::vector<float> pixels(48 * 48 * 4);
        if (in) in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, pixels.data());
        return pixels;
    }

    /// One transfer function for every render, so none depends on the volume's statistics.
    std::string tf() {
        std::ofstream(dir.path("tf.json")) << R"({"points": [[0, 0, 0, 0, 0], [150, 1, 1, 1, 0.4]]})";
        return dir.path("tf.json");
    }

    test::TempDir dir;
    LabelledScene scene;
};

double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
    double worst = 0.0;
    for (std::size_t n = 0; n < a.size(); ++n) worst = std::max(worst, double(std::abs(a[n] - b[n])));
    return worst;
}

}  // namespace

TEST_F(CliLabels, LabelsOnAnotherGridAreRefusedUnlessResampled) {
    FloatVolume coarse(openvdb::Coord(16, 10, 8), 1);
    coarse.worldFromIndex.setToScale(openvdb::Vec3d(2.0));
    for (float& v : coarse.values) v = 1.0f;
    writeNifti(dir.path("coarse.nii"), coarse);
    const std::string out = dir.path("mismatch.vdb");
    const test::CommandResult refused =
        runGvr("ingest -q '" + scene.image + "' -o '" + out + "' --labels '" + dir.path("coarse.nii") + "'", dir);
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_EQ(test::lineCount(refused.err), 1u) << refused.err;
    EXPECT_NE(refused.err.find("coarse.nii: is 16x10x8 voxels"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("--resample-labels"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(out));

    const test::CommandResult resampled = runGvr("ingest -q '" + scene.image + "' -o '" + out + "' --labels '" +
                                                     dir.path("coarse.nii") + "' --resample-labels --json",
                                                 dir);
    ASSERT_EQ(resampled.exitCode, 0) << resampled.err;
    EXPECT_EQ(nlohmann::json::parse(resampled.out)["labels"], (nlohmann::json{{"1", "label_1"}}));

    const test::CommandResult notLabels = runGvr(
        "ingest -q '" + scene.image + "' -o '" + dir.path("other.vdb") + "' --labels '" + scene.image + "'", dir);
    EXPECT_EQ(notLabels.exitCode, 2);
    EXPECT_NE(notLabels.err.find("not an integer"), std::string::npos) << notLabels.err;
}

TEST_F(CliLabels, PerStructureBudgetsAddUpAndEveryGaussianKeepsItsLabel) {
    const test::CommandResult run = fit("all", "both.gvr", "--gaussians 100");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json report = nlohmann::json::parse(run.out);
    ASSERT_EQ(report["structures"].size(), 2u);
    std::size_t budgets = 0, gaussians = 0;
    for (const auto& s : report["structures"]) {
        budgets += s["budget"].get<std::size_t>();
        gaussians += s["gaussians"].get<std::size_t>();
    }
    EXPECT_EQ(budgets, 100u);
    EXPECT_EQ(gaussians, report["gaussians"].get<std::size_t>());
    EXPECT_GT(report["structures"][0]["budget"], report["structures"][1]["budget"]);  // the left blob is larger

    const GaussianAsset asset = readAsset(dir.path("both.gvr"));
    ASSERT_EQ(asset.labels.size(), asset.params.count());
    EXPECT_EQ(asset.labelTable.nameOf(2), "Right");
    const auto left = std::count(asset.labels.begin(), asset.labels.end(), 1);
    EXPECT_EQ(std::size_t(left), report["structures"][0]["gaussians"].get<std::size_t>());
    for (std::size_t g = 0; g < asset.params.count(); ++g) {  // seeded inside their own blob
        const float x = asset.params.at(kMeans, g)[0];
        if (asset.labels[g] == 1) {
            EXPECT_LT(x, 18.0f) << g;
        }
        if (asset.labels[g] == 2) {
            EXPECT_GT(x, 14.0f) << g;
        }
    }
}

TEST_F(CliLabels, AHiddenStructureContributesNothing) {
    // Each file quantises over its own ranges; fine bit depths keep that rounding far
    // below what this test is about, the selection of structures.
    const std::string fine = "--mean-step 0.001 --rotation-bits 15 --scale-bits 16 --amplitude-bits 16";
    ASSERT_EQ(fit("all", "both.gvr", fine).exitCode, 0);
    ASSERT_EQ(fit("Left", "left.gvr", fine).exitCode, 0);
    const std::vector<float> hidden = render("both.gvr", "--hide Right", "hidden.png");
    const std::vector<float> fittedAlone = render("left.gvr", "", "alone.png");
    const std::vector<float> everything = render("both.gvr", "", "all.png");
    // The same Gaussians, finely quantised over each file's own ranges: at most one 8-bit level apart.
    EXPECT_LE(maxDifference(hidden, fittedAlone), 1.01 / 255.0);
    EXPECT_GT(maxDifference(hidden, everything), 0.1);  // the right blob is visible when shown
    EXPECT_EQ(maxDifference(render("both.gvr", "--show 1", "shown.png"), hidden), 0.0);

    const test::CommandResult exported =
        runGvr("export -q '" + dir.path("both.gvr") + "' -o '" + dir.path("left.vdb") + "' --show Left --json", dir);
    ASSERT_EQ(exported.exitCode, 0) << exported.err;
    const test::CommandResult alone =
        runGvr("export -q '" + dir.path("left.gvr") + "' -o '" + dir.path("alone.vdb") + "' --json", dir);
    ASSERT_EQ(alone.exitCode, 0) << alone.err;
    const test::CommandResult same =
        runGvr("eval '" + dir.path("alone.vdb") + "' '" + dir.path("left.vdb") + "' --json", dir);
    ASSERT_EQ(same.exitCode, 0) << same.err;
    const nlohmann::json psnr = nlohmann::json::parse(same.out)["psnr"];
    EXPECT_TRUE(psnr.is_null() || psnr.get<double>() > 60.0) << psnr;
}

TEST_F(CliLabels, UnknownStructuresAreNamedWithTheValidOnes) {
    const test::CommandResult badFit = fit("Middle", "x.gvr");
    EXPECT_EQ(badFit.exitCode, 2);
    EXPECT_NE(badFit.err.find("no structure is named 'Middle'; valid: 1 Left, 2 Right"), std::string::npos)
        << badFit.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.gvr")));
    ASSERT_EQ(fit("all", "both.gvr").exitCode, 0);
    const test::CommandResult badRender =
        runGvr("render -q '" + dir.path("both.gvr") + "' -o '" + dir.path("x.png") + "' --show 7", dir);
    EXPECT_EQ(badRender.exitCode, 2);
    EXPECT_NE(badRender.err.find("--show: no structure has label 7; valid: 1 Left, 2 Right"), std::string::npos)
        << badRender.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.png")));
    const test::CommandResult unlabelled =
        runGvr("render -q '" + scene.grid + "' -o '" + dir.path("y.png") + "' --show 1", dir);
    EXPECT_EQ(unlabelled.exitCode, 2);
}

TEST_F(CliLabels, EvalReportsEachStructure) {
    ASSERT_EQ(fit("all", "both.gvr").exitCode, 0);
    const test::CommandResult run =
        runGvr("eval '" + scene.grid + "' '" + dir.path("both.gvr") + "' --labels '" + scene.grid + "' --json", dir);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const nlohmann::json structures = nlohmann::json::parse(run.out)["structures"];
    ASSERT_EQ(structures.size(), 2u);
    EXPECT_EQ(structures[0]["name"], "Left");
    for (const auto& s : structures) {
        EXPECT_GT(s["voxels"].get<int>(), 100);
        EXPECT_GT(s["psnr"].get<double>(), 15.0) << s;
        EXPECT_GT(s["ssim"].get<double>(), 0.3) << s;
        EXPECT_LE(s["ssim"].get<double>(), 1.0) << s;
    }
    // An exact copy scores infinity on every structure.
    const test::CommandResult self = runGvr(
        "eval '" + scene.grid + "' '" + scene.grid + "' --labels '" + scene.grid + "' --structures Right --json", dir);
    ASSERT_EQ(self.exitCode, 0) << self.err;
    EXPECT_TRUE(nlohmann::json::parse(self.out)["structures"][0]["psnr"].is_null());
}

TEST_F(CliLabels, EvalTakesTheAtlasAsTheUserHasIt) {
    ASSERT_EQ(fit("all", "both.gvr").exitCode, 0);
    const std::string compare = "eval '" + scene.grid + "' '" + dir.path("both.gvr") + "' --json --labels ";
    const test::CommandResult fromGrid = runGvr(compare + "'" + scene.grid + "'", dir);
    const test::CommandResult fromAtlas =
        runGvr(compare + "'" + scene.labels + "' --label-names '" + scene.names + "'", dir);
    ASSERT_EQ(fromGrid.exitCode, 0) << fromGrid.err;
    ASSERT_EQ(fromAtlas.exitCode, 0) << fromAtlas.err;
    EXPECT_EQ(nlohmann::json::parse(fromAtlas.out)["structures"], nlohmann::json::parse(fromGrid.out)["structures"]);
    // export --like takes the source volume as well as its ingested grid.
    for (const std::string& like : {scene.image, scene.grid}) {
        const test::CommandResult exported = runGvr(
            "export -q '" + dir.path("both.gvr") + "' -o '" + dir.path("like.vdb") + "' --like '" + like + "' --json",
            dir);
        ASSERT_EQ(exported.exitCode, 0) << exported.err;
        EXPECT_EQ(nlohmann::json::parse(exported.out)["dims"], (nlohmann::json{32, 20, 16})) << exported.out;
    }
}

TEST_F(CliLabels, FitTakesTheSourceAndItsAtlasAsTheUserHasThem) {
    ASSERT_EQ(fit("all", "from-grid.gvr").exitCode, 0);
    const test::CommandResult fromSource =
        runGvr("fit -q '" + scene.image + "' -o '" + dir.path("from-source.gvr") + "' --labels all --label-volume '" +
                   scene.labels + "' --label-names '" + scene.names + "' --iterations 40 --batch 2048 --threads 1",
               dir);
    ASSERT_EQ(fromSource.exitCode, 0) << fromSource.err;
    EXPECT_EQ(test::readBytes(dir.path("from-source.gvr")), test::readBytes(dir.path("from-grid.gvr")));
    const test::CommandResult namesAlone =
        runGvr("fit -q '" + scene.image + "' -o '" + dir.path("x.gvr") + "' --labels all --label-names '" +
                   scene.names + "' --iterations 5",
               dir);
    EXPECT_EQ(namesAlone.exitCode, 2);
    EXPECT_NE(namesAlone.err.find("--label-volume"), std::string::npos) << namesAlone.err;
}

TEST_F(CliLabels, LabelStylesRecolourAndFadeOneStructure) {
    ASSERT_EQ(fit("all", "both.gvr").exitCode, 0);
    const std::vector<float> everything = render("both.gvr", "", "all.png");
    const std::vector<float> hidden = render("both.gvr", "--hide Right", "hidden.png");

    std::ofstream(dir.path("faded.json")) << R"({"Right": {"opacity": 0}})";
    EXPECT_EQ(maxDifference(render("both.gvr", "--label-style '" + dir.path("faded.json") + "'", "faded.png"), hidden),
              0.0);

    std::ofstream(dir.path("red.json")) << R"({"2": {"color": [1, 0, 0]}})";
    const std::vector<float> red = render("both.gvr", "--label-style '" + dir.path("red.json") + "'", "red.png");
    const std::vector<float> rightAlone = render("both.gvr", "--show Right", "right.png");
    double redness = 0.0, untouched = 0.0;
    int rightPixels = 0;
    for (std::size_t p = 0; p < everything.size(); p += 4) {
        const bool right = std::abs(everything[p + 3] - hidden[p + 3]) > 0.05f;
        if (right) {
            redness += red[p] - 0.5 * (red[p + 1] + red[p + 2]);
            ++rightPixels;
        } else if (rightAlone[p + 3] == 0.0f) {  // where the right blob shows nothing at all
            for (int c = 0; c < 4; ++c)
                untouched = std::max(untouched, double(std::abs(red[p + c] - everything[p + c])));
        }
    }
    ASSERT_GT(rightPixels, 20);
    EXPECT_GT(redness / rightPixels, 0.1);  // the right blob is drawn red
    EXPECT_LE(untouched, 2.01 / 255.0);     // the left one as before

    std::ofstream(dir.path("bad.json")) << R"({"Middle": {"color": [1, 0, 0]}})";
    const test::CommandResult bad = runGvr("render -q '" + dir.path("both.gvr") + "' -o '" + dir.path("bad.png") +
                                               "' --label-style '" + dir.path("bad.json") + "'",
                                           dir);
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.err.find("no structure is named 'Middle'"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("bad.png")));
}

TEST_F(CliLabels, BadLabelInputsAreOneLineErrorsWithoutOutput) {
    std::ofstream(dir.path("bad-names.txt")) << "1 Left\nseventeen Right\n";
    const std::string out = dir.path("named.vdb");
    const test::CommandResult names = runGvr("ingest -q '" + scene.image + "' -o '" + out + "' --labels '" +
                                                 scene.labels + "' --label-names '" + dir.path("bad-names.txt") + "'",
                                             dir);
    EXPECT_EQ(names.exitCode, 2);
    EXPECT_EQ(test::lineCount(names.err), 1u) << names.err;
    EXPECT_NE(names.err.find("bad-names.txt: line 2 is not \"ID NAME ...\""), std::string::npos) << names.err;
    EXPECT_FALSE(std::filesystem::exists(out));

    const std::string plain = dir.path("plain.vdb");
    ASSERT_EQ(runGvr("ingest -q '" + scene.image + "' -o '" + plain + "'", dir).exitCode, 0);
    const test::CommandResult unlabelled =
        runGvr("fit -q '" + plain + "' -o '" + dir.path("p.gvr") + "' --labels all --iterations 5", dir);
    EXPECT_EQ(unlabelled.exitCode, 2);
    EXPECT_EQ(test::lineCount(unlabelled.err), 1u) << unlabelled.err;
    EXPECT_NE(unlabelled.err.find("holds no label grid; ingest the image with --labels"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir.path("p.gvr")));

    const test::CommandResult evalNoLabels =
        runGvr("eval '" + plain + "' '" + plain + "' --labels '" + plain + "'", dir);
    EXPECT_EQ(evalNoLabels.exitCode, 2);
    EXPECT_EQ(test::lineCount(evalNoLabels.err), 1u) << evalNoLabels.err;

    // A label volume that is missing, or whose samples are not labels, names itself.
    const std::string missing = dir.path("missing.nii");
    for (const auto& [labels, problem] : {std::pair<std::string, std::string>{missing, missing},
                                          std::pair<std::string, std::string>{scene.image, scene.image}}) {
        const test::CommandResult run = runGvr("eval '" + plain + "' '" + plain + "' --labels '" + labels + "'", dir);
        EXPECT_EQ(run.exitCode, 2) << labels;
        EXPECT_EQ(test::lineCount(run.err), 1u) << run.err;
        EXPECT_NE(run.err.find(problem + ":"), std::string::npos) << run.err;
    }
    const test::CommandResult like =
        runGvr("export -q '" + plain + "' -o '" + dir.path("like.vdb") + "' --like '" + missing + "'", dir);
    EXPECT_EQ(like.exitCode, 2);
    EXPECT_EQ(test::lineCount(like.err), 1u) << like.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("like.vdb")));
}
